// Primary-ray generation exactly as CONVENTIONS specifies (bit-identical across programs).
#pragma once

#include <span>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

/// A pinhole camera's frame for one image size and antialiasing factor: everything a sample's
/// direction is made of (CONVENTIONS), so that a tracer can remake a camera tile's directions
/// in registers (src/geom/camera_simd.h) bit for bit instead of loading them.
struct CameraFrame {
    Vec3f position, forward, right, up2;
    float h = 0.f, aspect = 1.f;
    int width = 0, height = 0, aa = 1;

    /// (2u - 1) h aspect of sample column i of pixel column x, as CONVENTIONS writes it.
    float a(int x, int i) const {
        const float k = float(aa);
        const float u = (float(x) + (float(i) + 0.5f) / k) / float(width);
        return (2.f * u - 1.f) * h * aspect;
    }
    /// (2v - 1) h of sample row j of pixel row y.
    float b(int y, int j) const {
        const float k = float(aa);
        const float v = (float(y) + (float(j) + 0.5f) / k) / float(height);
        return (2.f * v - 1.f) * h;
    }
    /// normalize(forward + a right - b up2).
    Vec3f direction(float a, float b) const { return normalize(forward + a * right - b * up2); }
};

/// A tile of camera rays as its camera made them: the frame and the pixel of the tile's first
/// sample (its sample column sc is sample sc % K of pixel x0 + sc / K; rows likewise).
struct CameraTile {
    const CameraFrame* frame = nullptr;
    int x0 = 0, y0 = 0;
};

/// The orthonormal frame of a pinhole camera for one image size and antialiasing factor.
class CameraRays {
public:
    /// Throws rtt::Error for a degenerate camera (target == position, up parallel to the view,
    /// fovy outside (0, 180)), or a zero size.
    CameraRays(const Camera& camera, int width, int height, int aa);

    /// Direction of sample (i, j) of pixel (x, y):
    ///   u = (x + (i + 0.5) / K) / W,  v = (y + (j + 0.5) / K) / H
    ///   dir = normalize(forward + (2u - 1) * h * aspect * right - (2v - 1) * h * up2)
    /// Pixels outside the image (padding) follow the same formula.
    Vec3f direction(int x, int y, int i, int j) const {
        return frame_.direction(frame_.a(x, i), frame_.b(y, j));
    }
    Vec3f origin() const { return frame_.position; }
    const CameraFrame& frame() const { return frame_; }
    /// The camera part of tile (tx, ty)'s rays, or of a region starting there (RayTile::camera).
    CameraTile tile(int tx, int ty) const { return {&frame_, 4 * tx, 4 * ty}; }

    /// The (4K)^2 primary rays of 4x4-pixel tile (tx, ty) into `out`, in tile sample order:
    /// out[sr * 4K + sc] is sample (sc % K, sr % K) of pixel (4 tx + sc / K, 4 ty + sr / K),
    /// with t in [0, inf). Every place that shoots camera tiles (renderer, benchmarks, tests)
    /// uses this, so they all trace the same rays.
    void tile_rays(int tx, int ty, std::span<Ray> out) const;
    /// The same for the `cols` x `rows` tiles from tile (tx, ty) as one grid of 4K cols by
    /// 4K rows samples: out[sr * 4K cols + sc] is sample (sc % K, sr % K) of pixel
    /// (4 tx + sc / K, 4 ty + sr / K).
    void region_rays(int tx, int ty, int cols, int rows, std::span<Ray> out) const;

    int width() const { return frame_.width; }
    int height() const { return frame_.height; }
    int aa() const { return frame_.aa; }

private:
    CameraFrame frame_;
};

/// A camera looking at `box` from a diagonal, far enough to see all of it.
Camera default_camera_for(const Bbox3f& box, float fovy_deg = 50.f);

}  // namespace rtt
