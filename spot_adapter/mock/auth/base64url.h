// base64url without padding (RFC 4648 section 5), the alphabet of JWT segments.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace omniview::spot_mock {

std::string base64url_encode(std::string_view bytes);
// nullopt for characters outside the alphabet or an impossible length.
std::optional<std::string> base64url_decode(std::string_view text);

}  // namespace omniview::spot_mock
