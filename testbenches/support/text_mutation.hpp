// Random edits of a valid input, for the parsers' robustness tests: what a
// parser must survive is a text that is almost right.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <string_view>

namespace odoloc::tb {

// `text` with 1 .. max_edits edits, each at a random place: a character
// replaced by one of `alphabet`, 1 .. max_erase characters erased, or one of
// `alphabet` inserted.
inline std::string mutated(std::string text, std::mt19937_64& rng, std::string_view alphabet,
                           std::uint64_t max_edits, std::uint64_t max_erase) {
  const std::uint64_t edits = 1 + rng() % max_edits;
  for (std::uint64_t e = 0; e < edits && !text.empty(); ++e) {
    const std::size_t at = rng() % text.size();
    switch (rng() % 3) {
      case 0:
        text[at] = alphabet[rng() % alphabet.size()];
        break;
      case 1:
        text.erase(at, 1 + rng() % max_erase);
        break;
      default:
        text.insert(at, 1, alphabet[rng() % alphabet.size()]);
        break;
    }
  }
  return text;
}

}  // namespace odoloc::tb
