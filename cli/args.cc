#include "cli/args.h"

#include <algorithm>
#include <cctype>

namespace omniview::cli {
namespace {

bool contains(const std::vector<std::string>& list, const std::string& name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}

bool is_help(const std::string& word) { return word == "--help" || word == "-h"; }

bool is_long_option(const std::string& word) { return word.rfind("--", 0) == 0 && word != "--"; }

// "-x" is a mistyped option; "-1.5" (a negative number) and "-" (stdin by convention) are words.
bool looks_like_short_option(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && word[1] != '-' && !std::isdigit(static_cast<unsigned char>(word[1])) &&
         word[1] != '.';
}

}  // namespace

Args::Args(const std::vector<std::string>& argv, const std::vector<std::string>& switches) {
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& a = argv[i];
    if (!is_long_option(a)) {
      positional_.push_back(a);
      continue;
    }
    std::string name = a.substr(2), value;
    const auto eq = name.find('=');
    const bool is_switch = contains(switches, name);
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    } else if (!is_switch) {
      if (i + 1 >= argv.size()) throw UsageError("--" + name + " needs a value");
      value = argv[++i];
    }
    values_[name].push_back(value);
  }
}

Args Args::parse(const std::vector<std::string>& argv, const OptionSpec& spec) {
  Args args;
  if (std::any_of(argv.begin(), argv.end(), is_help)) {
    args.help_requested_ = true;
    return args;
  }
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& word = argv[i];
    if (!is_long_option(word)) {
      if (looks_like_short_option(word)) throw UsageError("unknown option " + word + " (see --help)");
      args.positional_.push_back(word);
      continue;
    }
    const size_t eq = word.find('=');
    const std::string name = word.substr(2, eq == std::string::npos ? std::string::npos : eq - 2);
    const bool is_switch = contains(spec.switches, name);
    if (!is_switch && !contains(spec.single, name) && !contains(spec.repeatable, name)) {
      throw UsageError("unknown option --" + name + " (see --help)");
    }
    std::string value;
    if (is_switch) {
      if (eq != std::string::npos) throw UsageError("--" + name + " takes no value");
    } else if (eq != std::string::npos) {
      value = word.substr(eq + 1);
    } else if (i + 1 < argv.size() && !is_long_option(argv[i + 1])) {
      value = argv[++i];
    } else {
      // Rather than take the next option as this one's value (--rig --view v.yaml).
      throw UsageError("--" + name + " needs a value");
    }
    if (contains(spec.single, name) && args.has(name)) {
      throw UsageError("--" + name + " given twice ('" + args.get(name) + "' and '" + value + "'); give it once");
    }
    args.values_[name].push_back(value);
  }
  return args;
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second.back();
}

std::string Args::required(const std::string& name) const {
  if (!has(name)) throw UsageError("missing --" + name);
  return get(name);
}

const std::vector<std::string>& Args::all(const std::string& name) const {
  static const std::vector<std::string> none;
  auto it = values_.find(name);
  return it == values_.end() ? none : it->second;
}

void Args::allow_only(const std::vector<std::string>& known) const {
  for (const auto& [name, _] : values_) {
    if (!contains(known, name)) throw UsageError("unknown option --" + name + " (see --help)");
  }
}

std::string count_of(size_t n, const std::string& singular, const std::string& plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

}  // namespace omniview::cli
