// The camera `rtt view` moves: orbit about a target, pan, dolly and fly, keeping the scene's up
// direction. No window or GL here, so the motions are unit-tested (tests/view_test.cpp).
#pragma once

#include <string>

#include "rtt/scene.h"

namespace rtt::view {

class OrbitCamera {
public:
    /// `scene_size` (the scene's bounding-box diagonal) scales flying and the closest dolly.
    OrbitCamera(const Camera& start, float scene_size);

    /// Turns the eye about the target: `yaw` about the up axis, `pitch` up or down (radians).
    /// The view never reaches the up axis (within 1 degree), where the camera would degenerate.
    void orbit(float yaw, float pitch);
    /// Moves eye and target sideways and up by fractions of the view's height at the target.
    void pan(float right, float up);
    /// Moves the eye towards the target: its distance times 0.9^steps (steps < 0 moves away).
    void dolly(float steps);
    /// Moves eye and target along the view, right and up, in units of the scene's size.
    void fly(float forward, float right, float up);
    /// Back to the start camera.
    void reset() { camera_ = start_; }

    /// Bit for bit the start camera until it is moved.
    const Camera& camera() const { return camera_; }

private:
    Camera start_;
    Camera camera_;
    float scene_size_;
};

/// "px,py,pz,tx,ty,tz,ux,uy,uz,fovy" with enough digits that `--camera` gives this camera back
/// bit for bit.
std::string camera_string(const Camera& camera);

}  // namespace rtt::view
