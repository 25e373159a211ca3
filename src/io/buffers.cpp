// CONVENTIONS' buffer files, byte for byte:
//   RTTH: char[4] "RTTH"; u32 version = 1; u32 width; u32 height; u32 spp; then
//         width*height*spp u32 triangle indices (0xFFFFFFFF = miss)
//   RTTS: char[4] "RTTS"; u32 version = 1; u32 width; u32 height; u32 spp; u32 nlights; then
//         width*height*spp u32 light masks
// All integers little-endian, whatever the host's byte order.
#include <array>
#include <bit>
#include <cerrno>
#include <cstring>
#include <memory>

#include "rtt/error.h"
#include "rtt/io.h"

namespace rtt {
namespace {

constexpr size_t chunk_words = size_t(1) << 16;

/// Writes u32 values little-endian, in chunks (no full copy of a large payload).
void write_words(std::FILE* f, std::span<const uint32_t> words) {
    std::array<uint8_t, 4 * 1024> bytes;
    for (size_t i = 0; i < words.size();) {
        const size_t n = std::min(words.size() - i, bytes.size() / 4);
        if constexpr (std::endian::native == std::endian::little) {
            std::memcpy(bytes.data(), words.data() + i, 4 * n);
        } else {
            for (size_t k = 0; k < n; ++k)
                for (int b = 0; b < 4; ++b) bytes[4 * k + b] = uint8_t(words[i + k] >> (8 * b));
        }
        if (std::fwrite(bytes.data(), 4, n, f) != n) return;  // commit() reports the error
        i += n;
    }
}

/// width * height * spp, or UINT64_MAX when that does not fit in 64 bits (a hostile header must
/// not wrap around to a small count that some payload matches).
uint64_t payload_words(uint32_t width, uint32_t height, uint32_t spp) {
    const uint64_t pixels = uint64_t(width) * uint64_t(height);  // < 2^64
    if (spp != 0 && pixels > UINT64_MAX / spp) return UINT64_MAX;
    return pixels * spp;
}

void write_buffer(const std::string& path, const char (&magic)[5], std::span<const uint32_t> header,
                  std::span<const uint32_t> payload) {
    write_file_atomically(path, [&](std::FILE* f) {
        std::fwrite(magic, 1, 4, f);
        write_words(f, header);
        write_words(f, payload);
    });
}

/// Reads a whole buffer file: magic, version, `header_count` header words after the version,
/// then the payload, whose size must match header[0] * header[1] * header[2] exactly.
class BufferReader {
public:
    BufferReader(const std::string& path, const char (&magic)[5]) : path_(path) {
        file_.reset(std::fopen(path.c_str(), "rb"));
        if (!file_) throw Error(path + ": cannot open: " + std::strerror(errno));
        char m[4];
        if (std::fread(m, 1, 4, file_.get()) != 4 || std::memcmp(m, magic, 4) != 0)
            throw Error(path + ": not a " + magic + " file (wrong magic)");
        const uint32_t version = word();
        if (version != buffer_version)
            throw Error(path + ": unsupported version " + std::to_string(version));
    }

    uint32_t word() {
        uint8_t b[4];
        if (std::fread(b, 1, 4, file_.get()) != 4) throw Error(path_ + ": truncated file");
        return uint32_t(b[0]) | uint32_t(b[1]) << 8 | uint32_t(b[2]) << 16 | uint32_t(b[3]) << 24;
    }

    /// Reads `count` payload words, then requires the end of the file.
    std::vector<uint32_t> payload(uint64_t count) {
        // Check the size against the file before allocating (a corrupt header must not
        // trigger a huge allocation).
        const long here = std::ftell(file_.get());
        std::fseek(file_.get(), 0, SEEK_END);
        const long end = std::ftell(file_.get());
        std::fseek(file_.get(), here, SEEK_SET);
        if (here < 0 || end < here || uint64_t(end - here) % 4 != 0 ||
            uint64_t(end - here) / 4 != count)  // not 4 * count: it can wrap
            throw Error(path_ + ": payload size does not match the header (expected " +
                        std::to_string(count) + " u32 values)");
        std::vector<uint32_t> out(count);
        std::vector<uint8_t> bytes(4 * chunk_words);
        for (uint64_t i = 0; i < count;) {
            const size_t n = size_t(std::min<uint64_t>(count - i, chunk_words));
            if (std::fread(bytes.data(), 4, n, file_.get()) != n)
                throw Error(path_ + ": truncated file");
            for (size_t k = 0; k < n; ++k)
                out[i + k] = uint32_t(bytes[4 * k]) | uint32_t(bytes[4 * k + 1]) << 8 |
                             uint32_t(bytes[4 * k + 2]) << 16 | uint32_t(bytes[4 * k + 3]) << 24;
            i += n;
        }
        return out;
    }

private:
    struct Closer {
        void operator()(std::FILE* f) const { std::fclose(f); }
    };
    std::string path_;
    std::unique_ptr<std::FILE, Closer> file_;
};

void check_payload(const std::string& path, uint64_t expected, size_t actual) {
    if (expected != actual)
        throw Error(path + ": buffer holds " + std::to_string(actual) + " samples, header says " +
                    std::to_string(expected));
}

}  // namespace

void write_hit_buffer(const std::string& path, const HitBuffer& b) {
    check_payload(path, payload_words(b.width, b.height, b.spp), b.hits.size());
    const uint32_t header[] = {buffer_version, b.width, b.height, b.spp};
    write_buffer(path, "RTTH", header, b.hits);
}

HitBuffer read_hit_buffer(const std::string& path) {
    BufferReader r(path, "RTTH");
    HitBuffer b;
    b.width = r.word();
    b.height = r.word();
    b.spp = r.word();
    b.hits = r.payload(payload_words(b.width, b.height, b.spp));
    return b;
}

void write_shadow_buffer(const std::string& path, const ShadowBuffer& b) {
    check_payload(path, payload_words(b.width, b.height, b.spp), b.bits.size());
    if (b.nlights > 32) throw Error(path + ": at most 32 lights fit a shadow buffer");
    const uint32_t header[] = {buffer_version, b.width, b.height, b.spp, b.nlights};
    write_buffer(path, "RTTS", header, b.bits);
}

ShadowBuffer read_shadow_buffer(const std::string& path) {
    BufferReader r(path, "RTTS");
    ShadowBuffer b;
    b.width = r.word();
    b.height = r.word();
    b.spp = r.word();
    b.nlights = r.word();
    if (b.nlights > 32) throw Error(path + ": more than 32 lights in the header");
    b.bits = r.payload(payload_words(b.width, b.height, b.spp));
    return b;
}

}  // namespace rtt
