// A small, independent VCD well-formedness checker for tests.
//
// Why independent: a test that checks the VcdWriter with the writer's own
// assumptions proves nothing. This parses the text as a viewer would, reports
// what is wrong (with line numbers), and keeps the declared vars and each one's
// value history so a test can read a waveform back:
//
//   std::ifstream file(path);
//   const auto vcd = odoloc::tb::check_vcd(file);
//   ASSERT_TRUE(vcd.ok()) << vcd.error_text();
//   EXPECT_EQ(vcd.value_at("odoloc.counter.count", 120), 6U);
//
// Checked: $date, $version, $timescale (1ns) and $enddefinitions present;
// scopes balanced; each $var has a positive width and a unique id; $dumpvars
// gives every var a value; no value change before the first timestamp
// (GTKWave's vcd2fst drops those); timestamps strictly increase; each value change
// names a declared id, a vector fits the declared width, scalars only on 1-bit
// vars.
#pragma once

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <istream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace odoloc::tb {

struct VcdVar {
  std::string name;  // scoped, dot-separated: "odoloc.counter.count"
  int width = 0;
  std::string id;
};

struct VcdChange {
  std::uint64_t time = 0;  // 0 before the first timestamp
  std::string bits;        // as written, without the 'b'
};

struct VcdCheckResult {
  std::vector<std::string> errors;
  std::vector<VcdVar> vars;
  std::vector<std::vector<VcdChange>> history;  // per var, in file order
  std::size_t timestamps = 0;

  [[nodiscard]] bool ok() const { return errors.empty(); }

  [[nodiscard]] std::string error_text() const {
    std::string text;
    for (const auto& e : errors) {
      text.append(e).append("\n");
    }
    return text;
  }

  [[nodiscard]] const VcdVar* find(std::string_view scoped_name) const {
    const auto it = std::find_if(vars.begin(), vars.end(),
                                 [&](const VcdVar& v) { return v.name == scoped_name; });
    return it == vars.end() ? nullptr : &*it;
  }

  // The value at `time` (the last change at or before it). nullopt: no such
  // signal, no value yet, or x/z bits.
  [[nodiscard]] std::optional<std::uint64_t> value_at(std::string_view scoped_name,
                                                      std::uint64_t time) const {
    const VcdVar* var = find(scoped_name);
    if (var == nullptr)
      return std::nullopt;
    const auto& changes = history[static_cast<std::size_t>(var - vars.data())];
    const auto after =
        std::upper_bound(changes.begin(), changes.end(), time,
                         [](std::uint64_t t, const VcdChange& change) { return t < change.time; });
    if (after == changes.begin())
      return std::nullopt;
    std::uint64_t value = 0;
    for (const char c : std::prev(after)->bits) {
      if (c != '0' && c != '1')
        return std::nullopt;
      value = (value << 1) | (c == '1' ? 1U : 0U);
    }
    return value;
  }
};

namespace detail {

class VcdTokens {
 public:
  explicit VcdTokens(std::istream& in) {
    std::ostringstream all;
    all << in.rdbuf();
    text_ = std::move(all).str();
  }

  bool next(std::string_view& token) {
    while (pos_ < text_.size() && is_space(text_[pos_])) {
      line_ += text_[pos_++] == '\n' ? 1 : 0;
    }
    if (pos_ == text_.size())
      return false;
    const std::size_t start = pos_;
    while (pos_ < text_.size() && !is_space(text_[pos_])) {
      ++pos_;
    }
    token = std::string_view(text_).substr(start, pos_ - start);
    return true;
  }
  [[nodiscard]] std::size_t line() const { return line_; }

 private:
  static bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
  std::string text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
};

inline std::optional<std::uint64_t> parse_number(std::string_view text) {
  std::uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size())
    return std::nullopt;
  return value;
}

}  // namespace detail

inline VcdCheckResult check_vcd(std::istream& in) {
  constexpr std::size_t kMaxErrors = 50;
  VcdCheckResult r;
  detail::VcdTokens tokens(in);
  const auto error = [&](const std::string& message) {
    if (r.errors.size() < kMaxErrors) {
      r.errors.push_back("line " + std::to_string(tokens.line()) + ": " + message);
    }
  };
  // The tokens of a "$keyword ... $end" section, after the keyword.
  const auto section = [&](std::string_view keyword) {
    std::vector<std::string_view> body;
    std::string_view token;
    while (tokens.next(token)) {
      if (token == "$end")
        return body;
      body.push_back(token);
    }
    error("missing $end for " + std::string(keyword));
    return body;
  };

  // ---- header ----
  std::map<std::string, bool> seen{
      {"$date", false}, {"$version", false}, {"$timescale", false}, {"$enddefinitions", false}};
  std::vector<std::string> scopes;
  std::map<std::string, std::size_t, std::less<>> index_of_id;
  std::string_view token;
  while (!seen["$enddefinitions"] && tokens.next(token)) {
    const std::string keyword(token);
    if (keyword.front() != '$') {
      error("unexpected '" + keyword + "' in the header");
      continue;
    }
    const auto body = section(keyword);
    if (seen.contains(keyword))
      seen[keyword] = true;
    if (keyword == "$date" || keyword == "$version" || keyword == "$comment") {
      continue;
    }
    if (keyword == "$timescale") {
      std::string joined;
      for (const auto t : body) {
        joined.append(joined.empty() ? "" : " ").append(t);
      }
      if (joined != "1ns" && joined != "1 ns")
        error("$timescale is '" + joined + "', not 1ns");
    } else if (keyword == "$scope") {
      if (body.size() != 2)
        error("$scope needs a type and a name");
      scopes.emplace_back(body.empty() ? "?" : body.back());
    } else if (keyword == "$upscope") {
      if (scopes.empty()) {
        error("$upscope without an open $scope");
      } else {
        scopes.pop_back();
      }
    } else if (keyword == "$var") {
      if (body.size() != 4 && body.size() != 5) {
        error("$var needs: type width id name [range]");
        continue;
      }
      VcdVar var;
      const auto width = detail::parse_number(body[1]);
      var.width = width && *width > 0 && *width <= 1'000'000 ? static_cast<int>(*width) : 0;
      if (var.width == 0)
        error("$var " + std::string(body[3]) + " has no positive width");
      var.id = body[2];
      for (const auto& s : scopes) {
        var.name.append(s).append(".");
      }
      var.name.append(body[3]);
      if (body.size() == 5)
        var.name.append(body[4]);
      if (!index_of_id.emplace(var.id, r.vars.size()).second) {
        error("$var " + var.name + " reuses id '" + var.id + "'");
      }
      r.vars.push_back(std::move(var));
    } else if (keyword == "$enddefinitions") {
      if (!scopes.empty())
        error(std::to_string(scopes.size()) + " $scope(s) still open");
    } else {
      error("unexpected '" + keyword + "' in the header");
    }
  }
  for (const auto& [keyword, present] : seen) {
    if (!present)
      error("missing " + keyword);
  }
  r.history.resize(r.vars.size());

  // ---- value changes ----
  std::optional<std::uint64_t> time;
  std::string_view open_block;  // $dumpvars, $dumpall, $dumpon, $dumpoff
  bool seen_dumpvars = false;
  std::vector<bool> initialised(r.vars.size(), false);
  const auto change = [&](std::string_view id, std::string_view bits, bool scalar) {
    const auto it = index_of_id.find(id);
    if (it == index_of_id.end()) {
      error("value change for undeclared id '" + std::string(id) + "'");
      return;
    }
    const VcdVar& var = r.vars[it->second];
    if (scalar && var.width != 1) {
      error("scalar change for " + std::to_string(var.width) + "-bit " + var.name);
    }
    if (std::cmp_greater(bits.size(), var.width)) {
      error(std::to_string(bits.size()) + " bits for " + std::to_string(var.width) + "-bit " +
            var.name);
    }
    if (!time)
      error("value change for " + var.name + " before the first timestamp (readers drop it)");
    if (open_block == "$dumpvars")
      initialised[it->second] = true;
    r.history[it->second].push_back({time.value_or(0), std::string(bits)});
  };
  const auto is_bits = [](std::string_view bits) {
    return !bits.empty() && bits.find_first_not_of("01xXzZ") == std::string_view::npos;
  };
  while (tokens.next(token)) {
    if (token.front() == '#') {
      const auto t = detail::parse_number(token.substr(1));
      if (!t) {
        error("bad timestamp '" + std::string(token) + "'");
      } else if (time && *t <= *time) {
        error("time " + std::to_string(*t) + " does not follow " + std::to_string(*time));
      } else {
        time = t;
      }
      ++r.timestamps;
    } else if (token == "$dumpvars" || token == "$dumpall" || token == "$dumpon" ||
               token == "$dumpoff") {
      if (!open_block.empty())
        error(std::string(token) + " inside " + std::string(open_block));
      seen_dumpvars = seen_dumpvars || token == "$dumpvars";
      open_block = token;
    } else if (token == "$end") {
      if (open_block.empty())
        error("$end without an open section");
      if (open_block == "$dumpvars") {
        for (std::size_t i = 0; i < r.vars.size(); ++i) {
          if (!initialised[i])
            error("$dumpvars gives no value to " + r.vars[i].name);
        }
      }
      open_block = {};
    } else if (token == "$comment") {
      section(token);
    } else if (token.front() == '$') {
      error("unexpected '" + std::string(token) + "' after $enddefinitions");
    } else if (token.front() == 'b' || token.front() == 'B') {
      const auto bits = token.substr(1);
      if (!is_bits(bits))
        error("bad vector value '" + std::string(token) + "'");
      std::string_view id;
      if (!tokens.next(id)) {
        error("vector value without an id");
      } else {
        change(id, bits, false);
      }
    } else if (token.front() == 'r' || token.front() == 'R') {
      std::string_view id;
      if (!tokens.next(id))
        error("real value without an id");
    } else if (is_bits(token.substr(0, 1)) && token.size() > 1) {
      change(token.substr(1), token.substr(0, 1), true);
    } else {
      error("unexpected token '" + std::string(token) + "'");
    }
  }
  if (!open_block.empty())
    error("missing $end for " + std::string(open_block));
  if (!seen_dumpvars)
    error("missing $dumpvars");
  return r;
}

inline VcdCheckResult check_vcd(const std::string& text) {
  std::istringstream in(text);
  return check_vcd(in);
}

}  // namespace odoloc::tb
