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

// Every option a command accepts, by kind. Names are without the leading "--".
struct OptionSpec {
  std::vector<std::string> switches;    // take no value
  std::vector<std::string> single;      // take one value, at most once
  std::vector<std::string> repeatable;  // take one value, any number of times
};

class Args {
 public:
  // `switches` take no value; every other --name takes one. Knows nothing of unknown
  // options (see allow_only) or of repeats; parse() below checks both.
  Args(const std::vector<std::string>& argv, const std::vector<std::string>& switches);

  // Parses `argv` against `spec`. If --help or -h appears anywhere (even where a value is
  // expected), help_requested() is true and nothing else is checked: help always wins.
  // Otherwise throws UsageError for an unknown option, a missing value, a value given to a
  // switch, a single-valued option given twice, or a word starting with '-' that is no option.
  static Args parse(const std::vector<std::string>& argv, const OptionSpec& spec);

  bool help_requested() const { return help_requested_; }
  bool has(const std::string& name) const { return values_.count(name) > 0; }
  std::string get(const std::string& name, const std::string& fallback = "") const;
  std::string required(const std::string& name) const;
  const std::vector<std::string>& all(const std::string& name) const;
  const std::vector<std::string>& positional() const { return positional_; }
  // Fails naming the first flag not in `known` (catches typos like --veiw).
  void allow_only(const std::vector<std::string>& known) const;

 private:
  Args() = default;

  std::map<std::string, std::vector<std::string>> values_;
  std::vector<std::string> positional_;
  bool help_requested_ = false;
};

// "1 value", "2 values": counts in messages.
std::string count_of(size_t n, const std::string& singular, const std::string& plural);

}  // namespace omniview::cli
