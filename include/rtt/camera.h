// Primary-ray generation exactly as CONVENTIONS specifies (bit-identical across programs).
#pragma once

#include <span>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

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
    Vec3f direction(int x, int y, int i, int j) const;
    Vec3f origin() const { return pos_; }

    /// The (4K)^2 primary rays of 4x4-pixel tile (tx, ty) into `out`, in tile sample order:
    /// out[sr * 4K + sc] is sample (sc % K, sr % K) of pixel (4 tx + sc / K, 4 ty + sr / K),
    /// with t in [0, inf). Every place that shoots camera tiles (renderer, benchmarks, tests)
    /// uses this, so they all trace the same rays.
    void tile_rays(int tx, int ty, std::span<Ray> out) const;
    /// The same for the `cols` x `rows` tiles from tile (tx, ty) as one grid of 4K cols by
    /// 4K rows samples: out[sr * 4K cols + sc] is sample (sc % K, sr % K) of pixel
    /// (4 tx + sc / K, 4 ty + sr / K).
    void region_rays(int tx, int ty, int cols, int rows, std::span<Ray> out) const;

    int width() const { return width_; }
    int height() const { return height_; }
    int aa() const { return aa_; }

private:
    Vec3f pos_, forward_, right_, up2_;
    float h_ = 0.f, aspect_ = 1.f;
    int width_ = 0, height_ = 0, aa_ = 1;
};

/// A camera looking at `box` from a diagonal, far enough to see all of it.
Camera default_camera_for(const Bbox3f& box, float fovy_deg = 50.f);

}  // namespace rtt
