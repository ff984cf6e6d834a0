#include "spot_adapter/mock/control/control_command.h"

#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <grpcpp/grpcpp.h>

#include "omniview/spotmock/v1/control.grpc.pb.h"
#include "spot_adapter/mock/auth/certificates.h"
#include "spot_adapter/mock/server/mock_options.h"

namespace omniview::spot_mock {
namespace {

namespace v1 = omniview::spotmock::v1;

void print_help() {
  std::cout << "usage: spot-mock control --port P --certs DIR [--host HOST] [actions]\n"
               "\n"
               "Talks to a running spot-mock's control service (TLS, trusting DIR/ca.pem).\n"
               "Actions run in this order, whatever the order given:\n"
               "  --set KEY=VALUE    change a fault: latency_ms, fail_probability,\n"
               "                     image_error_probability, corrupt_probability,\n"
               "                     wrong_size_probability (0..1), away (true|false); repeatable\n"
               "  --joint NAME=RAD   set a leg joint's angle (fl.hx ... hr.kn); repeatable\n"
               "  --expire-tokens    every token issued so far stops working\n"
               "  --faults           print the faults as KEY=VALUE lines (also after --set)\n"
               "  --counters         print the counters as KEY=VALUE lines\n"
               "                     (image_requests.<source>=N per requested source)\n"
               "  --reset-counters   zero the counters (after printing them, with --counters)\n"
               "\n"
               "  --host HOST        where the mock listens (default 127.0.0.1)\n"
               "  --help             this text\n";
}

struct ControlArgs {
  std::string host = "127.0.0.1";
  int port = -1;
  std::string certs_dir;
  v1::Faults faults;
  bool set_faults = false, print_faults = false;
  std::map<std::string, double> joints;
  bool expire_tokens = false, print_counters = false, reset_counters = false;
};

std::pair<std::string, std::string> split_assignment(const std::string& flag, const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw std::invalid_argument(flag + " needs KEY=VALUE");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

void set_fault(v1::Faults& f, const std::string& text) {
  const auto [key, value] = split_assignment("--set", text);
  const std::string flag = "--set " + key;
  if (key == "latency_ms") {
    f.set_latency_ms(static_cast<uint32_t>(parse_int(flag, value, 0, 60000)));
  } else if (key == "fail_probability") {
    f.set_fail_probability(parse_double(flag, value));
  } else if (key == "image_error_probability") {
    f.set_image_error_probability(parse_double(flag, value));
  } else if (key == "corrupt_probability") {
    f.set_corrupt_probability(parse_double(flag, value));
  } else if (key == "wrong_size_probability") {
    f.set_wrong_size_probability(parse_double(flag, value));
  } else if (key == "away") {
    if (value != "true" && value != "false" && value != "1" && value != "0") {
      throw std::invalid_argument(flag + " needs true or false");
    }
    f.set_away(value == "true" || value == "1");
  } else {
    throw std::invalid_argument("--set: unknown fault '" + key + "'");
  }
}

ControlArgs parse(const std::vector<std::string>& args) {
  ControlArgs a;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    const auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw std::invalid_argument(arg + " needs a value");
      return args[++i];
    };
    if (arg == "--host") {
      a.host = value();
    } else if (arg == "--port") {
      a.port = parse_int(arg, value(), 1, 65535);
    } else if (arg == "--certs") {
      a.certs_dir = value();
    } else if (arg == "--set") {
      set_fault(a.faults, value());
      a.set_faults = true;
    } else if (arg == "--joint") {
      const auto [name, angle] = split_assignment(arg, value());
      a.joints[name] = parse_double("--joint " + name, angle);
    } else if (arg == "--expire-tokens") {
      a.expire_tokens = true;
    } else if (arg == "--faults") {
      a.print_faults = true;
    } else if (arg == "--counters") {
      a.print_counters = true;
    } else if (arg == "--reset-counters") {
      a.reset_counters = true;
    } else {
      throw std::invalid_argument("unknown argument '" + arg + "'");
    }
  }
  if (a.port < 0 || a.certs_dir.empty()) throw std::invalid_argument("--port and --certs are required");
  return a;
}

std::unique_ptr<v1::SpotMockControl::Stub> connect(const ControlArgs& a) {
  std::ifstream in(ca_cert_file(a.certs_dir));
  if (!in) throw std::runtime_error("cannot read " + ca_cert_file(a.certs_dir));
  std::stringstream ca;
  ca << in.rdbuf();
  grpc::ChannelArguments channel_args;
  channel_args.SetSslTargetNameOverride(mock_authorities().front());  // api.spot.robot
  grpc::SslCredentialsOptions tls;
  tls.pem_root_certs = ca.str();
  const auto creds = grpc::SslCredentials(tls);
  return v1::SpotMockControl::NewStub(grpc::CreateCustomChannel(a.host + ":" + std::to_string(a.port), creds, channel_args));
}

void print(const v1::Faults& f) {
  std::cout << "latency_ms=" << f.latency_ms() << "\nfail_probability=" << f.fail_probability()
            << "\nimage_error_probability=" << f.image_error_probability()
            << "\ncorrupt_probability=" << f.corrupt_probability()
            << "\nwrong_size_probability=" << f.wrong_size_probability()
            << "\naway=" << (f.away() ? "true" : "false") << "\n";
}

void print(const v1::Counters& c) {
  std::cout << "get_image_calls=" << c.get_image_calls() << "\nlogins_ok=" << c.logins_ok()
            << "\nlogins_failed=" << c.logins_failed() << "\ntoken_refreshes=" << c.token_refreshes()
            << "\nauth_rejections=" << c.auth_rejections()
            << "\nlist_image_sources_calls=" << c.list_image_sources_calls()
            << "\nget_point_cloud_calls=" << c.get_point_cloud_calls()
            << "\nget_robot_state_calls=" << c.get_robot_state_calls() << "\n";
  const std::map<std::string, uint64_t> sorted(c.image_requests_by_source().begin(), c.image_requests_by_source().end());
  for (const auto& [source, n] : sorted) std::cout << "image_requests." << source << "=" << n << "\n";
}

std::unique_ptr<grpc::ClientContext> context() {
  auto ctx = std::make_unique<grpc::ClientContext>();
  ctx->set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(10));
  return ctx;
}

// Throws with the RPC's name and status when it failed.
void check(const char* rpc, const grpc::Status& status) {
  if (!status.ok()) {
    throw std::runtime_error(std::string(rpc) + " failed: " + std::to_string(status.error_code()) + " " +
                             status.error_message());
  }
}

}  // namespace

int run_control_command(const std::vector<std::string>& args) {
  for (const auto& arg : args) {
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
  }
  ControlArgs a;
  try {
    a = parse(args);
  } catch (const std::invalid_argument& e) {
    std::cerr << "spot-mock control: " << e.what() << " (see spot-mock control --help)\n";
    return 2;
  }
  try {
    const auto stub = connect(a);
    v1::Faults faults_now;
    if (a.set_faults) {
      v1::SetFaultsRequest request;
      *request.mutable_faults() = a.faults;
      v1::SetFaultsResponse response;
      check("SetFaults", stub->SetFaults(context().get(), request, &response));
      faults_now = response.faults();
    } else if (a.print_faults) {
      v1::GetFaultsResponse response;
      check("GetFaults", stub->GetFaults(context().get(), {}, &response));
      faults_now = response.faults();
    }
    if (!a.joints.empty()) {
      v1::SetJointAnglesRequest request;
      request.mutable_positions()->insert(a.joints.begin(), a.joints.end());
      v1::SetJointAnglesResponse response;
      check("SetJointAngles", stub->SetJointAngles(context().get(), request, &response));
    }
    if (a.expire_tokens) {
      v1::ExpireTokensResponse response;
      check("ExpireTokens", stub->ExpireTokens(context().get(), {}, &response));
      std::cout << "expired_tokens=" << response.expired() << "\n";
    }
    if (a.set_faults || a.print_faults) print(faults_now);
    if (a.print_counters || a.reset_counters) {
      v1::GetCountersRequest request;
      request.set_reset(a.reset_counters);
      v1::GetCountersResponse response;
      check("GetCounters", stub->GetCounters(context().get(), request, &response));
      if (a.print_counters) print(response.counters());
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "spot-mock control: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace omniview::spot_mock
