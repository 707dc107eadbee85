#include "odoloc/rtl/vcd.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <limits>
#include <stdexcept>
#include <utility>

namespace odoloc::rtl {

namespace {

constexpr std::string_view kClkId = "!";  // identifier 0; signals take 1, 2, ...
constexpr std::uint64_t kHalfPeriodNs = kFabricClockPeriodNs / 2;

// Identifier codes: base-94 digits over the printable characters '!'..'~'.
std::string make_id(std::size_t n) {
  constexpr std::size_t kDigits = 94;
  std::string id;
  do {
    id.push_back(static_cast<char>('!' + n % kDigits));
    n /= kDigits;
  } while (n != 0);
  return id;
}

// A VCD reference is one whitespace-free token.
void check_name(std::string_view name, std::string_view what) {
  bool ok = !name.empty();
  for (const char c : name) {
    ok = ok && c > ' ' && c <= '~';
  }
  if (!ok) {
    throw std::invalid_argument("VcdWriter: " + std::string(what) + " name '" + std::string(name) +
                                "' must be non-empty printable ASCII without spaces");
  }
}

std::string utc_now() {
  using namespace std::chrono;
  const auto now = floor<seconds>(system_clock::now());
  const auto today = floor<days>(now);
  const year_month_day ymd{today};
  const hh_mm_ss time{now - today};
  const auto two = [](auto v) { return std::to_string(100 + static_cast<long>(v)).substr(1); };
  return std::to_string(static_cast<int>(ymd.year())) + "-" +
         two(static_cast<unsigned>(ymd.month())) + "-" + two(static_cast<unsigned>(ymd.day())) +
         " " + two(time.hours().count()) + ":" + two(time.minutes().count()) + ":" +
         two(time.seconds().count()) + " UTC";
}

}  // namespace

VcdWriter::VcdWriter(std::ostream& out, std::string top_scope)
    : out_(out), top_scope_(std::move(top_scope)) {
  check_name(top_scope_, "top scope");
}

void VcdWriter::begin_declarations() {
  if (declaring_ || declared_) {
    throw std::logic_error("VcdWriter::declare: called twice");
  }
  declaring_ = true;
}

void VcdWriter::declare_scope(std::string_view name) {
  check_name(name, "scope");
  definitions_.append("$scope module ").append(name).append(" $end\n");
  ++open_scopes_;
}

void VcdWriter::declare_upscope() {
  if (open_scopes_ == 0) {
    throw std::logic_error("VcdWriter::declare: the block's trace calls leave() without enter()");
  }
  definitions_.append("$upscope $end\n");
  --open_scopes_;
}

void VcdWriter::declare_var(std::string_view name, int width, std::uint64_t initial) {
  check_name(name, "signal");
  ids_.push_back(make_id(ids_.size() + 1));
  widths_.push_back(width);
  last_values_.push_back(initial);
  definitions_.append("$var wire ")
      .append(std::to_string(width))
      .append(" ")
      .append(ids_.back())
      .append(" ")
      .append(name)
      .append(" $end\n");
}

void VcdWriter::end_declarations() {
  if (open_scopes_ != 0) {
    throw std::logic_error("VcdWriter::declare: the block's trace calls enter() without leave()");
  }
  out_ << "$date\n  " << utc_now() << "\n$end\n"
       << "$version\n  odoloc rtl model VcdWriter\n$end\n"
       << "$timescale 1ns $end\n"
       << "$scope module " << top_scope_ << " $end\n"
       << "$var wire 1 " << kClkId << " clk $end\n"
       << definitions_ << "$upscope $end\n"
       << "$enddefinitions $end\n"
       // The initial values belong to time 0: readers drop value changes
       // before the first timestamp (GTKWave's vcd2fst does).
       << "#0\n$dumpvars\n0" << kClkId << '\n';
  for (std::size_t i = 0; i < ids_.size(); ++i) {
    write_value(i, last_values_[i]);
  }
  out_ << "$end\n";
  definitions_ = std::string{};
  declared_ = true;
}

void VcdWriter::begin_sample(std::uint64_t cycle) {
  if (!declared_) {
    throw std::logic_error("VcdWriter::sample: called before declare()");
  }
  if (last_cycle_ && cycle <= *last_cycle_) {
    throw std::logic_error("VcdWriter::sample: cycle " + std::to_string(cycle) +
                           " does not follow cycle " + std::to_string(*last_cycle_));
  }
  if (cycle > (std::numeric_limits<std::uint64_t>::max() - kHalfPeriodNs) / kFabricClockPeriodNs) {
    throw std::logic_error("VcdWriter::sample: cycle " + std::to_string(cycle) +
                           " overflows the time in ns");
  }
  // Cycle 0's rising edge is at the initial values' #0, which is written.
  if (last_cycle_ || cycle != 0) {
    out_ << '#' << cycle * kFabricClockPeriodNs << '\n';
  }
  last_cycle_ = cycle;
  out_ << '1' << kClkId << '\n';
}

void VcdWriter::record_change(std::size_t index, std::uint64_t bits) {
  if (index >= last_values_.size()) {
    throw std::logic_error("VcdWriter::sample: the block's trace visits more than the " +
                           std::to_string(last_values_.size()) + " signals declared");
  }
  last_values_[index] = bits;
  write_value(index, bits);
}

void VcdWriter::end_sample(std::size_t visited) {
  if (visited != last_values_.size()) {
    throw std::logic_error("VcdWriter::sample: the block's trace visits " +
                           std::to_string(visited) + " signals, declared were " +
                           std::to_string(last_values_.size()));
  }
  out_ << '#' << *last_cycle_ * kFabricClockPeriodNs + kHalfPeriodNs << "\n0" << kClkId << '\n';
}

// 1-bit: "1!"; wider: "b101 !" with leading zeros dropped (VCD zero-extends).
void VcdWriter::write_value(std::size_t index, std::uint64_t bits) {
  std::array<char, 66> text{};
  std::size_t length = 0;
  if (widths_[index] == 1) {
    text[length++] = bits != 0 ? '1' : '0';
  } else {
    text[length++] = 'b';
    for (int bit = std::max(1, static_cast<int>(std::bit_width(bits))) - 1; bit >= 0; --bit) {
      text[length++] = ((bits >> bit) & 1U) != 0 ? '1' : '0';
    }
    text[length++] = ' ';
  }
  out_.write(text.data(), static_cast<std::streamsize>(length));
  out_ << ids_[index] << '\n';
}

}  // namespace odoloc::rtl
