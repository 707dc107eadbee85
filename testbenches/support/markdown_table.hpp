// Markdown table rows as the generators write them: cells are separated by
// pipes, and a backslash escapes the next character (so `\|` is text).
#pragma once

#include <cstddef>
#include <string>

namespace odoloc::tb {

// The unescaped pipes of a table row: cells + 1 for "| a | b |".
inline std::size_t unescaped_pipes(const std::string& row) {
  std::size_t pipes = 0;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (row[i] == '\\') {
      ++i;
      continue;
    }
    pipes += row[i] == '|' ? 1 : 0;
  }
  return pipes;
}

}  // namespace odoloc::tb
