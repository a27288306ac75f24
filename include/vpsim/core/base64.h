#pragma once
/// @file
/// RFC 4648 base64, for figures and 3D data embedded in HTML and SVG.

#include <string>
#include <string_view>

namespace vpsim {

std::string base64(std::string_view bytes);

}  // namespace vpsim
