// Unpredictable text for passwords and token signatures (std::random_device: the OS's
// entropy source on Linux).
#pragma once

#include <cstddef>
#include <string>

namespace omniview::spot_mock {

std::string random_alphanumeric(size_t length);  // [A-Za-z0-9]
std::string random_bytes(size_t length);

}  // namespace omniview::spot_mock
