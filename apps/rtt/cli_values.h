// Parsers of the small text values the command line takes (--camera, --light x,y,z, --size WxH).
// Not part of the library: they build the internal target rtt_cli_values, which the program,
// its tests and the fuzz targets link, so all three reach exactly the code the program runs.
#pragma once

#include <string>
#include <vector>

#include "rtt/math.h"
#include "rtt/scene.h"

namespace rtt {

/// Parses "x,y,z": three finite floats, blanks allowed around each. `what` names the value in
/// error messages ("--light"). Throws rtt::Error for anything else (a missing or extra value,
/// an empty item, trailing text, NaN, infinity, or a number beyond float range).
Vec3f parse_vec3(const std::string& text, const std::string& what);

/// Parses "WxH" (or "WXH") of whole decimal numbers into width and height; the range is
/// RenderOptions::validate's business. Throws rtt::Error on malformed text or a number beyond
/// int range.
void parse_size(const std::string& text, int& width, int& height);

/// Parses "px,py,pz,tx,ty,tz,ux,uy,uz,fovy"; throws rtt::Error on malformed text.
Camera parse_camera(const std::string& text);

/// Reads a camera path: one camera per line as parse_camera takes it (blank lines and lines
/// starting with '#' are skipped), or, when the file starts with '[', a JSON list of cameras,
/// each the 10 numbers as an array or an object with the scene format's camera keys. Throws
/// rtt::Error "file:line: ..." on a bad line, or when the file is missing or holds no camera.
std::vector<Camera> read_camera_path(const std::string& path);

/// `pattern` with its frame number directive (%d, or %0Nd with N <= 9) replaced by `frame`;
/// `pattern` itself when it has none and `frames` is 1. Throws rtt::Error naming `option` when
/// several frames would share one name, or for any other '%' directive.
std::string frame_file_name(const std::string& option, const std::string& pattern, size_t frame,
                            size_t frames);

}  // namespace rtt
