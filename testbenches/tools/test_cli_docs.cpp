// The documentation's examples, run: every command of README.md and
// docs/*.md that calls the host tool (`odoloc ...`, `$B ...`) runs on the
// simulated board, and where the docs show its output, the output must be
// what the docs say.
//
// Which blocks (docs/host-tool.md, "Examples are tested"):
//  - ```console blocks are transcripts: `$ COMMAND` lines (a trailing `\`
//    continues them), then the output the docs promise, stdout and stderr
//    together. A line `...` stands for any number of lines. No output shown:
//    only the exit status is checked. Output starting `odoloc: ` is an error
//    and must come with a non-zero exit status; otherwise the status is 0.
//  - ```sh blocks with a line starting `odoloc ` or `$B ` run whole, in a
//    fresh directory, under `set -e`; `B=...` lines are replaced by the built
//    binary.
//  - Every command runs in a fresh directory holding a link to the
//    repository's examples/, so `examples/locate/layout.yaml` works as from
//    the repository's root.
//  - Lines naming a spidev target need a board and are skipped, as are sh
//    blocks using sigrok-cli, gtkwave, gnuplot or GNU parallel where they
//    are not installed; ```text blocks (synopses) are not run.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

struct Block {
  std::string file;
  std::size_t line = 0;  // of the opening fence
  std::string lang;
  std::vector<std::string> lines;
};

std::vector<Block> blocks_of(const fs::path& path) {
  std::vector<Block> blocks;
  std::ifstream in(path);
  std::string text;
  Block* open = nullptr;
  for (std::size_t n = 1; std::getline(in, text); ++n) {
    const std::size_t indent = text.find_first_not_of(' ');
    const std::string_view body =
        indent == std::string::npos ? std::string_view{} : std::string_view{text}.substr(indent);
    if (body.starts_with("```")) {
      if (open != nullptr) {
        open = nullptr;
        continue;
      }
      blocks.push_back({path.filename().string(), n, std::string{body.substr(3)}, {}});
      open = &blocks.back();
      continue;
    }
    if (open != nullptr)
      open->lines.push_back(text);
  }
  return blocks;
}

std::vector<fs::path> documents() {
  const fs::path root{ODOLOC_SOURCE_DIR};
  std::vector<fs::path> docs{root / "README.md"};
  for (const fs::directory_entry& e : fs::directory_iterator(root / "docs")) {
    if (e.path().extension() == ".md")
      docs.push_back(e.path());
  }
  std::ranges::sort(docs);
  return docs;
}

bool calls_tool(std::string_view command) {
  for (const std::string_view word : {"odoloc ", "$B "}) {
    for (std::size_t at = command.find(word); at != std::string_view::npos;
         at = command.find(word, at + 1)) {
      // At the start, or after a pipe, `;`, `&&` or a space (not in a path).
      if (at == 0 || command[at - 1] == ' ' || command[at - 1] == '|')
        return true;
    }
  }
  return false;
}

struct Run {
  int code = -1;
  std::string out;
};

// `script` in a fresh temporary directory with `odoloc` on PATH, $B set and
// examples/ linked.
Run shell(const std::string& script) {
  static int serial = 0;
  const fs::path dir =
      fs::path{::testing::TempDir()} / fmt::format("odoloc_docs_{}_{}", ::getpid(), ++serial);
  fs::create_directories(dir);
  const fs::path file = dir / "example.sh";
  const fs::path binary{ODOLOC_CLI};
  fs::create_directory_symlink(fs::path{ODOLOC_SOURCE_DIR} / "examples", dir / "examples");
  std::ofstream(file) << fmt::format("set -e\ncd '{}'\nexport PATH='{}':\"$PATH\"\nB='{}'\n{}\n",
                                     dir.string(), binary.parent_path().string(), binary.string(),
                                     script);
  Run r;
  FILE* pipe = ::popen(fmt::format("/bin/sh '{}' 2>&1", file.string()).c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "popen failed";
    return r;
  }
  std::array<char, 4096> buffer{};
  for (std::size_t n; (n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0;)
    r.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  fs::remove_all(dir);
  return r;
}

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream s(text);
  for (std::string line; std::getline(s, line);)
    lines.push_back(line);
  return lines;
}

// `expected` with "..." lines matching any run of lines.
bool matches(const std::vector<std::string>& expected, std::size_t e,
             const std::vector<std::string>& actual, std::size_t a) {
  if (e == expected.size())
    return a == actual.size();
  if (expected[e] == "...") {
    for (std::size_t skip = a; skip <= actual.size(); ++skip) {
      if (matches(expected, e + 1, actual, skip))
        return true;
    }
    return false;
  }
  return a < actual.size() && expected[e] == actual[a] && matches(expected, e + 1, actual, a + 1);
}

std::size_t g_commands = 0, g_compared = 0;

void check_console(const Block& b) {
  for (std::size_t i = 0; i < b.lines.size();) {
    if (!b.lines[i].starts_with("$ ")) {
      ++i;
      continue;
    }
    const std::size_t at = b.line + 1 + i;
    std::string command = b.lines[i].substr(2);
    while (command.ends_with("\\") && ++i < b.lines.size())
      command += "\n" + b.lines[i];
    std::vector<std::string> expected;
    for (++i; i < b.lines.size() && !b.lines[i].starts_with("$ "); ++i)
      expected.push_back(b.lines[i]);
    if (!calls_tool(command) || command.find("spidev") != std::string::npos)
      continue;
    ++g_commands;
    SCOPED_TRACE(fmt::format("{}:{}: $ {}", b.file, at, command));
    const Run r = shell(command);
    const bool error = !expected.empty() && expected.front().starts_with("odoloc: ");
    if (error)
      EXPECT_NE(r.code, 0) << r.out;
    else
      EXPECT_EQ(r.code, 0) << r.out;
    if (expected.empty())
      continue;
    ++g_compared;
    EXPECT_TRUE(matches(expected, 0, split_lines(r.out), 0))
        << "documented:\n"
        << fmt::format("{}", fmt::join(expected, "\n")) << "\nprinted:\n"
        << r.out;
  }
}

void check_sh(const Block& b) {
  bool tool = false;
  std::string script;
  bool skipping = false;  // a spidev line and its continuations
  for (const std::string& line : b.lines) {
    const std::string_view body = std::string_view{line}.substr(
        std::min(line.size(), line.find_first_not_of(' ') == std::string::npos
                                  ? line.size()
                                  : line.find_first_not_of(' ')));
    const bool continued = skipping;
    skipping = false;
    if (continued || line.find("spidev") != std::string::npos || body.starts_with("B=")) {
      skipping = line.ends_with("\\");
      continue;
    }
    tool |= body.starts_with("odoloc ") || body.starts_with("$B ");
    script += line + "\n";
  }
  if (!tool)
    return;
  // Optional viewers and decoders: the example needs them installed.
  for (const char* optional : {"sigrok-cli", "gtkwave", "gnuplot", "parallel"}) {
    if (script.find(optional) != std::string::npos &&
        shell(fmt::format("command -v {} >/dev/null", optional)).code != 0) {
      std::cout << fmt::format("{}:{}: skipped, {} is not installed\n", b.file, b.line, optional);
      return;
    }
  }
  ++g_commands;
  SCOPED_TRACE(fmt::format("{}:{}: ```sh block", b.file, b.line));
  const Run r = shell(script);
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST(CliDocs, EveryDocumentedCommandRunsAndPrintsWhatTheDocsSay) {
  for (const fs::path& doc : documents()) {
    for (const Block& b : blocks_of(doc)) {
      if (b.lang == "console")
        check_console(b);
      else if (b.lang == "sh")
        check_sh(b);
    }
  }
  // The manual has examples with output; a parser that found none is broken.
  std::cout << fmt::format("{} documented commands run, {} outputs compared\n", g_commands,
                           g_compared);
  EXPECT_GE(g_commands, 10U);
  EXPECT_GE(g_compared, 5U);
}

}  // namespace
