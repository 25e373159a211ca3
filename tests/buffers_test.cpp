#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>

#include "rtt/error.h"
#include "rtt/io.h"
#include "temp_dir.h"

namespace rtt {
namespace {

namespace fs = std::filesystem;

using test::TempDir;

std::vector<uint8_t> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const std::string& path, const std::vector<uint8_t>& b) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

TEST(Buffers, HitBufferRoundTrip) {
    const TempDir dir("hits");
    HitBuffer b{3, 2, 4, {}};
    for (uint32_t i = 0; i < 3 * 2 * 4; ++i) b.hits.push_back(i % 5 == 0 ? 0xFFFFFFFFu : i * 7919u);
    write_hit_buffer(dir.file("h.rtth"), b);
    const HitBuffer r = read_hit_buffer(dir.file("h.rtth"));
    EXPECT_EQ(r.width, 3u);
    EXPECT_EQ(r.height, 2u);
    EXPECT_EQ(r.spp, 4u);
    EXPECT_EQ(r.hits, b.hits);
    EXPECT_EQ(dir.entries().size(), 1u);  // no temporary left behind
}

TEST(Buffers, ShadowBufferRoundTrip) {
    const TempDir dir("shadows");
    ShadowBuffer b{2, 2, 1, 32, {0u, 1u, 0x80000000u, 0xFFFFFFFFu}};
    write_shadow_buffer(dir.file("s.rtts"), b);
    const ShadowBuffer r = read_shadow_buffer(dir.file("s.rtts"));
    EXPECT_EQ(r.width, 2u);
    EXPECT_EQ(r.height, 2u);
    EXPECT_EQ(r.spp, 1u);
    EXPECT_EQ(r.nlights, 32u);
    EXPECT_EQ(r.bits, b.bits);
}

TEST(Buffers, ExactLittleEndianLayout) {
    const TempDir dir("layout");
    write_hit_buffer(dir.file("h.rtth"), HitBuffer{2, 1, 1, {0x01020304u, 0xFFFFFFFFu}});
    const std::vector<uint8_t> expected_hits = {'R', 'T', 'T', 'H', 1,    0,    0,    0,   2, 0,
                                                0,   0,   1,   0,   0,    0,    1,    0,   0, 0,
                                                4,   3,   2,   1,   0xFF, 0xFF, 0xFF, 0xFF};
    EXPECT_EQ(bytes_of(dir.file("h.rtth")), expected_hits);

    write_shadow_buffer(dir.file("s.rtts"), ShadowBuffer{1, 1, 1, 3, {0x05u}});
    const std::vector<uint8_t> expected_shadows = {
        'R', 'T', 'T', 'S', 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 3, 0, 0, 0, 5, 0, 0, 0};
    EXPECT_EQ(bytes_of(dir.file("s.rtts")), expected_shadows);
}

TEST(Buffers, ReaderRejectsBadFiles) {
    const TempDir dir("bad");
    write_hit_buffer(dir.file("good.rtth"), HitBuffer{2, 1, 1, {7u, 8u}});
    const std::vector<uint8_t> good = bytes_of(dir.file("good.rtth"));

    std::vector<uint8_t> magic = good;
    magic[3] = 'S';
    write_bytes(dir.file("magic.rtth"), magic);
    EXPECT_THROW(read_hit_buffer(dir.file("magic.rtth")), Error);

    std::vector<uint8_t> version = good;
    version[4] = 2;
    write_bytes(dir.file("version.rtth"), version);
    EXPECT_THROW(read_hit_buffer(dir.file("version.rtth")), Error);

    write_bytes(dir.file("short.rtth"), std::vector<uint8_t>(good.begin(), good.end() - 1));
    EXPECT_THROW(read_hit_buffer(dir.file("short.rtth")), Error);

    std::vector<uint8_t> longer = good;
    longer.push_back(0);
    write_bytes(dir.file("long.rtth"), longer);
    EXPECT_THROW(read_hit_buffer(dir.file("long.rtth")), Error);

    // A header announcing a huge payload must fail on the size check, not on allocation.
    std::vector<uint8_t> huge = good;
    huge[8] = huge[9] = huge[10] = huge[11] = 0xFF;
    huge[12] = huge[13] = huge[14] = huge[15] = 0xFF;
    write_bytes(dir.file("huge.rtth"), huge);
    EXPECT_THROW(read_hit_buffer(dir.file("huge.rtth")), Error);

    EXPECT_THROW(read_hit_buffer(dir.file("missing.rtth")), Error);
    EXPECT_THROW(read_shadow_buffer(dir.file("good.rtth")), Error);  // RTTH is not RTTS
}

TEST(Buffers, WriterRejectsMismatchedPayload) {
    const TempDir dir("mismatch");
    EXPECT_THROW(write_hit_buffer(dir.file("h.rtth"), HitBuffer{2, 2, 1, {1u, 2u, 3u}}), Error);
    EXPECT_THROW(write_shadow_buffer(dir.file("s.rtts"), ShadowBuffer{1, 1, 1, 33, {0u}}), Error);
    EXPECT_EQ(dir.entries().size(), 0u);
}

TEST(Buffers, FailedWriteLeavesNoFile) {
    const TempDir dir("atomic");
    const std::string path = dir.file("out.bin");
    // The writer fails half-way: nothing appears, not even the temporary.
    EXPECT_THROW(write_file_atomically(path,
                                       [](std::FILE* f) {
                                           std::fputs("half of it", f);
                                           throw std::runtime_error("disk on fire");
                                       }),
                 std::runtime_error);
    EXPECT_FALSE(fs::exists(path));
    EXPECT_EQ(dir.entries().size(), 0u);

    // An existing file survives a failed overwrite unchanged.
    write_file_atomically(path, [](std::FILE* f) { std::fputs("old", f); });
    EXPECT_THROW(write_file_atomically(path, [](std::FILE*) { throw std::runtime_error("no"); }),
                 std::runtime_error);
    const std::vector<uint8_t> old = bytes_of(path);
    EXPECT_EQ(std::string(old.begin(), old.end()), "old");
    EXPECT_EQ(dir.entries().size(), 1u);

    // An unwritable destination is an rtt::Error and creates nothing.
    EXPECT_THROW(write_hit_buffer(dir.file("no/such/folder/h.rtth"), HitBuffer{1, 1, 1, {0u}}),
                 Error);
    EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(Buffers, PngHasSignatureAndRejectsBadSizes) {
    const TempDir dir("png");
    const std::vector<uint8_t> rgb(4 * 3 * 3, 200);
    write_png(dir.file("a.png"), 4, 3, 3, rgb);
    const std::vector<uint8_t> b = bytes_of(dir.file("a.png"));
    ASSERT_GT(b.size(), 8u);
    EXPECT_EQ(std::vector<uint8_t>(b.begin(), b.begin() + 8),
              (std::vector<uint8_t>{0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'}));
    EXPECT_THROW(write_png(dir.file("b.png"), 5, 3, 3, rgb), Error);
    EXPECT_THROW(write_png(dir.file("c.png"), 4, 3, 2, rgb), Error);
    EXPECT_FALSE(fs::exists(dir.file("b.png")));
}

}  // namespace
}  // namespace rtt
