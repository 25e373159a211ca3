// Images beyond PNG: binary PPM / PGM, PFM and OpenEXR (linear float and arbitrary layers).
// OpenEXR writes into memory first (MemoryStream), so the file itself goes through
// write_file_atomically like every other output.
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfOutputFile.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "rtt/error.h"
#include "rtt/io.h"

namespace rtt {
namespace {

void require_size(const std::string& path, size_t have, size_t want) {
    if (have != want)
        throw Error(path + ": image data holds " + std::to_string(have) + " values, expected " +
                    std::to_string(want));
}

void put(std::FILE* f, const void* data, size_t bytes) {
    if (bytes && std::fwrite(data, 1, bytes, f) != bytes) throw Error("write failed");
}

/// An OpenEXR output stream into a byte vector.
class MemoryStream final : public Imf::OStream {
public:
    MemoryStream() : Imf::OStream("memory") {}
    void write(const char c[], int n) override {
        if (pos_ + uint64_t(n) > bytes_.size()) bytes_.resize(size_t(pos_) + size_t(n));
        std::memcpy(bytes_.data() + pos_, c, size_t(n));
        pos_ += uint64_t(n);
    }
    uint64_t tellp() override { return pos_; }
    void seekp(uint64_t pos) override { pos_ = pos; }
    const std::vector<char>& bytes() const { return bytes_; }

private:
    std::vector<char> bytes_;
    uint64_t pos_ = 0;
};

}  // namespace

void write_pnm(const std::string& path, int width, int height, int channels,
               std::span<const uint8_t> pixels) {
    if (channels != 1 && channels != 3) throw Error(path + ": PNM images have 1 or 3 channels");
    require_size(path, pixels.size(), size_t(width) * size_t(height) * size_t(channels));
    write_file_atomically(path, [&](std::FILE* f) {
        const std::string header = std::string(channels == 3 ? "P6" : "P5") + "\n" +
                                   std::to_string(width) + " " + std::to_string(height) + "\n255\n";
        put(f, header.data(), header.size());
        put(f, pixels.data(), pixels.size());
    });
}

void write_pfm(const std::string& path, int width, int height, std::span<const Vec3f> pixels) {
    require_size(path, pixels.size(), size_t(width) * size_t(height));
    static_assert(sizeof(Vec3f) == 12, "PFM rows are written straight from Vec3f");
    write_file_atomically(path, [&](std::FILE* f) {
        // Scale -1: little-endian (the x86-64 byte order of the floats written).
        const std::string header =
            "PF\n" + std::to_string(width) + " " + std::to_string(height) + "\n-1.0\n";
        put(f, header.data(), header.size());
        for (int y = height - 1; y >= 0; --y)
            put(f, pixels.data() + size_t(y) * size_t(width), size_t(width) * sizeof(Vec3f));
    });
}

void write_exr(const std::string& path, int width, int height,
               std::span<const ExrChannel> channels) {
    const size_t n = size_t(width) * size_t(height);
    for (const ExrChannel& c : channels)
        require_size(path + " (" + c.name + ")",
                     c.floats.empty() ? c.uints.size() : c.floats.size(), n);
    MemoryStream memory;
    try {
        Imf::Header header(width, height);
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (const ExrChannel& c : channels) {
            const bool is_float = !c.floats.empty();
            const Imf::PixelType type = is_float ? Imf::FLOAT : Imf::UINT;
            header.channels().insert(c.name, Imf::Channel(type));
            // OpenEXR reads through a non-const pointer but does not write when saving.
            char* base = is_float ? reinterpret_cast<char*>(const_cast<float*>(c.floats.data()))
                                  : reinterpret_cast<char*>(const_cast<uint32_t*>(c.uints.data()));
            frame.insert(c.name, Imf::Slice(type, base, 4, size_t(width) * 4));
        }
        Imf::OutputFile file(memory, header);
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {
        throw Error(path + ": cannot encode the EXR image: " + e.what());
    }
    write_file_atomically(
        path, [&](std::FILE* f) { put(f, memory.bytes().data(), memory.bytes().size()); });
}

}  // namespace rtt
