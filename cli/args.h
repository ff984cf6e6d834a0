// A small command-line parser: --flag value, --flag=value, repeated flags, switches.
// Enough for our subcommands without another dependency.
#pragma once

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace omniview::cli {

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // `switches` take no value; every other --name takes one.
  Args(const std::vector<std::string>& argv, const std::vector<std::string>& switches);

  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  std::string required(const std::string& name) const;
  const std::vector<std::string>& all(const std::string& name) const;
  const std::vector<std::string>& positional() const { return positional_; }
  // Fails naming the first flag not in `known` (catches typos like --veiw).
  void allow_only(const std::vector<std::string>& known) const;

 private:
  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
};

}  // namespace omniview::cli
