// Runs a fuzz target without libFuzzer, for CTest on any compiler: every file in the
// given corpus folders, plus deterministic mutations of each (bit flips, truncations,
// duplicated and deleted spans), so parsers meet malformed input on every CI run.
// Coverage-guided fuzzing proper: configure with clang and -DOMNIVIEW_FUZZ=ON.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {

void run(const std::string& input) {
  LLVMFuzzerTestOneInput(reinterpret_cast<const uint8_t*>(input.data()), input.size());
}

std::string mutate(std::string s, std::mt19937& rng) {
  if (s.empty()) return s;
  std::uniform_int_distribution<size_t> pos(0, s.size() - 1);
  switch (rng() % 5) {
    case 0: s[pos(rng)] ^= static_cast<char>(1u << (rng() % 8)); break;
    case 1: s.resize(pos(rng)); break;
    case 2: { const size_t a = pos(rng), n = std::min<size_t>(rng() % 64, s.size() - a); s.insert(a, s.substr(a, n)); break; }
    case 3: { const size_t a = pos(rng); s.erase(a, rng() % 32); break; }
    default: { const char* tokens[] = {"[", "]", "{", "}", ":", "-", "nan", "1e308", "-1", "0", "\n  ", "'", "&a", "*a"};
               s.insert(pos(rng), tokens[rng() % 14]); }
  }
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  constexpr int kMutationsPerSeed = 300;
  std::mt19937 rng(20211231);
  size_t runs = 0;
  for (int i = 1; i < argc; ++i) {
    for (const auto& entry : std::filesystem::directory_iterator(argv[i])) {
      std::ifstream in(entry.path(), std::ios::binary);
      const std::string seed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      run(seed);
      std::string current = seed;
      for (int m = 0; m < kMutationsPerSeed; ++m) {
        current = (m % 10 == 0) ? seed : mutate(current, rng);  // walk away from the seed, come back
        run(current);
      }
      runs += 1 + kMutationsPerSeed;
    }
  }
  std::cout << "ran " << runs << " inputs\n";
  return runs > 0 ? 0 : 1;
}
