// PLY's scalar types, shared by the structure check before assimp (ply_check.cpp) and rtt's own
// reader (import_ply.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace rtt::detail {

enum class PlyType : uint8_t { none, i8, u8, i16, u16, i32, u32, f32, f64 };

/// The type a header names ("uchar", "float32", ...); none for an unknown name.
inline PlyType ply_type(std::string_view t) {
    if (t == "char" || t == "int8") return PlyType::i8;
    if (t == "uchar" || t == "uint8") return PlyType::u8;
    if (t == "short" || t == "int16") return PlyType::i16;
    if (t == "ushort" || t == "uint16") return PlyType::u16;
    if (t == "int" || t == "int32") return PlyType::i32;
    if (t == "uint" || t == "uint32") return PlyType::u32;
    if (t == "float" || t == "float32") return PlyType::f32;
    if (t == "double" || t == "float64") return PlyType::f64;
    return PlyType::none;
}

/// Bytes of a binary value; 0 for none.
inline size_t ply_size(PlyType t) {
    switch (t) {
        case PlyType::i8:
        case PlyType::u8:
            return 1;
        case PlyType::i16:
        case PlyType::u16:
            return 2;
        case PlyType::i32:
        case PlyType::u32:
        case PlyType::f32:
            return 4;
        case PlyType::f64:
            return 8;
        case PlyType::none:
            break;
    }
    return 0;
}

inline bool ply_signed_integer(PlyType t) {
    return t == PlyType::i8 || t == PlyType::i16 || t == PlyType::i32;
}

inline bool ply_float(PlyType t) {
    return t == PlyType::f32 || t == PlyType::f64;
}

}  // namespace rtt::detail
