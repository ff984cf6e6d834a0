// What is wrong with the PEM files of the config's `tls:` section, checked when the config
// loads: gRPC would only fail later, with "cannot listen" and no hint which file is wrong.
#pragma once

#include <string>

namespace omniview {

// Each returns "" when fine, else what is wrong (for a message naming the config key).
// Holds at least one certificate; `key` names the config key ("tls.cert") for the hint.
std::string certificate_file_problem(const std::string& file, const std::string& key);
std::string private_key_file_problem(const std::string& file);  // holds an unencrypted private key
// The key in `key_file` belongs to the (first) certificate in `cert_file`. Both files
// must already have passed the checks above.
std::string key_pair_problem(const std::string& cert_file, const std::string& key_file);

}  // namespace omniview
