// spot-mock's TLS identity: one certificate per Spot authority, each with SAN DNS:<authority>,
// all signed by a CA the mock makes itself (clients trust ca.pem, as they would trust Boston
// Dynamics' root CA for a real robot).
#pragma once

#include <string>
#include <vector>

namespace omniview::spot_mock {

// The authorities a Spot client addresses (its TLS target-name override per channel).
const std::vector<std::string>& mock_authorities();  // api.spot.robot, auth.spot.robot, id.spot.robot

// The files in a certificate folder.
std::string ca_cert_file(const std::string& dir);                                  // DIR/ca.pem
std::string cert_file(const std::string& dir, const std::string& authority);       // DIR/<authority>.crt
std::string key_file(const std::string& dir, const std::string& authority);        // DIR/<authority>.key (0600)

// Makes `dir` and a fresh CA plus every authority's key and certificate (ECDSA P-256, via the
// `openssl` command) unless all the files are there already; returns whether it made them.
// The CA's key is thrown away: a new set replaces the old as a whole. Throws
// std::runtime_error with openssl's output when a step fails.
bool ensure_certificates(const std::string& dir);

}  // namespace omniview::spot_mock
