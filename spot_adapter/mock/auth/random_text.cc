#include "spot_adapter/mock/auth/random_text.h"

#include <random>
#include <string_view>

namespace omniview::spot_mock {

std::string random_alphanumeric(size_t length) {
  static constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  std::random_device device;
  std::uniform_int_distribution<size_t> pick(0, kAlphabet.size() - 1);
  std::string out;
  for (size_t i = 0; i < length; ++i) out.push_back(kAlphabet[pick(device)]);
  return out;
}

std::string random_bytes(size_t length) {
  std::random_device device;
  std::uniform_int_distribution<int> byte(0, 255);
  std::string out;
  for (size_t i = 0; i < length; ++i) out.push_back(static_cast<char>(byte(device)));
  return out;
}

}  // namespace omniview::spot_mock
