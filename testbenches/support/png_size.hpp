// The size a PNG file says it has (its IHDR chunk), for tests of pictures
// drawn by gnuplot.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>

namespace odoloc::tb {

struct PngSize {
  std::uint32_t width = 0, height = 0;
};

// Width and height from the IHDR chunk; zeros when `file` is not a PNG.
inline PngSize png_size(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<unsigned char, 24> header{};
  in.read(reinterpret_cast<char*>(header.data()), header.size());  // NOLINT: bytes
  static constexpr std::array<unsigned char, 8> kSignature = {0x89, 'P',  'N',  'G',
                                                              '\r', '\n', 0x1A, '\n'};
  if (!in || !std::equal(kSignature.begin(), kSignature.end(), header.begin()))
    return {};
  const auto be32 = [&](std::size_t at) {
    return std::uint32_t{header[at]} << 24 | std::uint32_t{header[at + 1]} << 16 |
           std::uint32_t{header[at + 2]} << 8 | std::uint32_t{header[at + 3]};
  };
  return {be32(16), be32(20)};
}

}  // namespace odoloc::tb
