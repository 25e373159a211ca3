// libFuzzer target: bytes as an RTTH or RTTS buffer file (read_hit_buffer, read_shadow_buffer).
// Any input must be read or refused with rtt::Error, without allocating more than the file
// holds; a file that reads back must be rewritten byte for byte (the layout has no slack).
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include "fuzz_util.h"
#include "rtt/io.h"

namespace {

std::vector<uint8_t> bytes_of(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using rtt::fuzz::require;
    const std::string path = rtt::fuzz::write_file("buffer.bin", data, size);
    const std::string copy = (rtt::fuzz::scratch_dir() / "copy.bin").string();
    const std::vector<uint8_t> input(data, data + size);
    rtt::fuzz::expect_only_rtt_errors([&] {
        const rtt::HitBuffer b = rtt::read_hit_buffer(path);
        require(b.hits.size() == uint64_t(b.width) * b.height * b.spp, "RTTH payload size");
        rtt::write_hit_buffer(copy, b);
        require(bytes_of(copy) == input, "RTTH read then written is not the same file");
    });
    rtt::fuzz::expect_only_rtt_errors([&] {
        const rtt::ShadowBuffer b = rtt::read_shadow_buffer(path);
        require(b.bits.size() == uint64_t(b.width) * b.height * b.spp, "RTTS payload size");
        require(b.nlights <= 32, "RTTS light count");
        rtt::write_shadow_buffer(copy, b);
        require(bytes_of(copy) == input, "RTTS read then written is not the same file");
    });
    return 0;
}
