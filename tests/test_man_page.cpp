// The man page and the CLI's help agree: it renders without warnings, documents every command,
// option and exit code that --help lists; --version prints the versions on stdout and exits 0, a
// usage error exits 2 with one line on stderr (docs/CONTRIBUTING.md, "Errors and exit codes").
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

struct RunResult {
  int exit_code = -1;  // -1 when the process did not exit normally
  std::string out;
  std::string err;
};

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Runs `command` through the shell, capturing stdout (pipe) and stderr (temporary file).
RunResult run(const std::string& command) {
  RunResult result;
  char err_path[] = "/tmp/untangle_test_man_XXXXXX";
  const int fd = mkstemp(err_path);
  if (fd < 0) return result;
  close(fd);
  FILE* pipe = popen((command + " 2>" + shell_quote(err_path)).c_str(), "r");
  if (pipe == nullptr) {
    std::remove(err_path);
    return result;
  }
  char buffer[4096];
  std::size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) result.out.append(buffer, n);
  const int status = pclose(pipe);
  if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
  result.err = read_file(err_path);
  std::remove(err_path);
  return result;
}

RunResult run_cli(const std::string& arguments) {
  return run(shell_quote(UNTANGLE_BINARY) + (arguments.empty() ? "" : " " + arguments));
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// The man page source with roff escapes that may sit inside an option name removed: `\-` is a
// minus sign, `\%` and `\&` are zero-width, `\c` joins lines, `\fB` etc. switch fonts.
std::string normalized_man_source() {
  std::string text = read_file(UNTANGLE_MAN_PAGE);
  text = std::regex_replace(text, std::regex(R"(\\-)"), "-");
  text = std::regex_replace(text, std::regex(R"(\\[%&c])"), "");
  text = std::regex_replace(text, std::regex(R"(\\f(\[[^\]]*\]|\(..|.))"), "");
  return text;
}

// The body of section `.SH NAME` (up to the next `.SH`), or "" when absent.
std::string man_section(const std::string& man, const std::string& name) {
  const std::regex heading("(^|\n)\\.SH +\"?" + name + "\"?[ \t]*\n");
  std::smatch m;
  if (!std::regex_search(man, m, heading)) return "";
  const std::size_t begin = static_cast<std::size_t>(m.position(0) + m.length(0));
  const std::size_t end = man.find("\n.SH", begin);
  return man.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

// Whether `word` occurs in `text` delimited by characters that cannot continue an option name.
bool contains_token(const std::string& text, const std::string& word) {
  auto continues = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_';
  };
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
    const bool left = at == 0 || !continues(text[at - 1]);
    const bool right = at + word.size() == text.size() || !continues(text[at + word.size()]);
    if (left && right) return true;
  }
  return false;
}

// Every `--long` and `-s` option named in a help text.
std::set<std::string> options_in_help(const std::string& help) {
  std::set<std::string> options;
  // A long name runs as far as name characters go (CLI11 may append "{false}" or "=VALUE"); a
  // short one is a single letter.
  const std::regex option(
      R"((?:^|[\s,\[|(!])(--[A-Za-z][A-Za-z0-9_-]*|-[A-Za-z](?![A-Za-z0-9_-])))");
  for (auto it = std::sregex_iterator(help.begin(), help.end(), option);
       it != std::sregex_iterator(); ++it) {
    options.insert((*it)[1].str());
  }
  return options;
}

// The subcommand names listed under "Subcommands:" in the top-level help.
std::vector<std::string> subcommands_in_help(const std::string& help) {
  std::vector<std::string> names;
  bool inside = false;
  for (const std::string& line : lines_of(help)) {
    if (line.rfind("Subcommands:", 0) == 0) {
      inside = true;
    } else if (inside) {
      std::smatch m;
      if (!std::regex_search(line, m, std::regex(R"(^\s+([a-z][a-z0-9_-]*)\b)"))) break;
      names.push_back(m[1].str());
    }
  }
  return names;
}

// The exit codes listed under "Exit codes:" in a help text.
std::vector<std::string> exit_codes_in_help(const std::string& help) {
  std::vector<std::string> codes;
  bool inside = false;
  for (const std::string& line : lines_of(help)) {
    if (line.rfind("Exit codes:", 0) == 0) {
      inside = true;
    } else if (inside) {
      std::smatch m;
      if (std::regex_search(line, m, std::regex(R"(^\s{1,3}([0-9]+)\s)"))) {
        codes.push_back(m[1].str());
      } else if (line.find_first_not_of(" \t") == std::string::npos) {
        break;
      }
    }
  }
  return codes;
}

TEST(ManPage, RendersWithoutWarnings) {
  const RunResult r = run("groff -man -Tutf8 -ww -z " + shell_quote(UNTANGLE_MAN_PAGE));
  EXPECT_EQ(r.exit_code, 0) << "groff failed (is groff-base installed? run scripts/setup.sh)\n"
                            << r.err;
  EXPECT_EQ(r.err, "") << "groff warnings for " << UNTANGLE_MAN_PAGE;
}

TEST(ManPage, DocumentsEveryCommandOptionAndExitCode) {
  const std::string man = normalized_man_source();
  ASSERT_FALSE(man.empty()) << "cannot read " << UNTANGLE_MAN_PAGE;
  const std::string commands = man_section(man, "COMMANDS");
  const std::string options = man_section(man, "OPTIONS");
  const std::string exit_status = man_section(man, "EXIT STATUS");
  ASSERT_FALSE(commands.empty()) << "no .SH COMMANDS";
  ASSERT_FALSE(options.empty()) << "no .SH OPTIONS";
  ASSERT_FALSE(exit_status.empty()) << "no .SH \"EXIT STATUS\"";

  const RunResult top = run_cli("--help");
  ASSERT_EQ(top.exit_code, 0) << top.err;
  const std::vector<std::string> subcommands = subcommands_in_help(top.out);
  ASSERT_FALSE(subcommands.empty()) << "no subcommands in --help:\n" << top.out;

  std::vector<std::pair<std::string, std::string>> helps{{"untangle --help", top.out}};
  for (const std::string& sub : subcommands) {
    // A command has a tagged paragraph of its own in COMMANDS: `.TP` then `.B[I] "sub ...`.
    const std::regex entry("\\.TP\n\\.[BI]+ +\"?" + sub + "\\b");
    EXPECT_TRUE(std::regex_search(commands, entry))
        << "command '" << sub << "' has no entry in COMMANDS";
    const RunResult r = run_cli(sub + " --help");
    ASSERT_EQ(r.exit_code, 0) << sub << " --help: " << r.err;
    helps.emplace_back("untangle " + sub + " --help", r.out);
  }

  std::size_t checked = 0;
  for (const auto& [source, help] : helps) {
    for (const std::string& option : options_in_help(help)) {
      ++checked;
      EXPECT_TRUE(contains_token(options, option))
          << option << " (from `" << source << "`) is not documented in OPTIONS";
    }
    for (const std::string& code : exit_codes_in_help(help)) {
      EXPECT_TRUE(std::regex_search(exit_status, std::regex("\\.TP\n\\.B +" + code + "\n")))
          << "exit code " << code << " (from `" << source << "`) is not in EXIT STATUS";
    }
  }
  // -h, --help, --version and the subcommands' options at least.
  EXPECT_GE(checked, 3u);
  EXPECT_TRUE(contains_token(options, "--version"));
}

// The option lines of a help text's "Options:" section: the name column (up to the description)
// and the description, continuation lines joined.
std::vector<std::pair<std::string, std::string>> option_lines(const std::string& help) {
  std::vector<std::pair<std::string, std::string>> out;
  bool inside = false;
  for (const std::string& line : lines_of(help)) {
    if (line.rfind("Options:", 0) == 0) {
      inside = true;
      continue;
    }
    if (!inside) continue;
    if (line.find_first_not_of(" \t") == std::string::npos) break;
    std::smatch m;
    if (std::regex_match(line, m, std::regex(R"(  (-\S*(?: \S+)*?)(?:  +(.*))?)"))) {
      out.emplace_back(m[1].str(), m[2].str());
    } else if (!out.empty()) {
      out.back().second += " " + std::regex_replace(line, std::regex(R"(^\s+)"), "");
    }
  }
  return out;
}

// The help texts of every subcommand, by name.
std::vector<std::pair<std::string, std::string>> subcommand_helps() {
  std::vector<std::pair<std::string, std::string>> helps;
  const RunResult top = run_cli("--help");
  for (const std::string& sub : subcommands_in_help(top.out)) {
    const RunResult r = run_cli(sub + " --help");
    helps.emplace_back(sub, r.out);
  }
  return helps;
}

// Each option has one line of its own, with no CLI11 artefact ("--a,--b{false}") in its name
// column, and states its default at most once.
TEST(ManPage, HelpListsEachOptionOnce) {
  const std::vector<std::pair<std::string, std::string>> helps = subcommand_helps();
  ASSERT_FALSE(helps.empty());
  for (const auto& [sub, help] : helps) {
    const auto lines = option_lines(help);
    EXPECT_FALSE(lines.empty()) << sub << " --help has no options:\n" << help;
    std::map<std::string, int> seen;
    for (const auto& [names, description] : lines) {
      EXPECT_EQ(names.find_first_of("{}"), std::string::npos)
          << "untangle " << sub << " --help: '" << names << "'";
      for (const std::string& option : options_in_help(names)) ++seen[option];
      std::size_t defaults = 0;
      for (std::size_t at = description.find("(default"); at != std::string::npos;
           at = description.find("(default", at + 1))
        ++defaults;
      EXPECT_LE(defaults, 1u) << "untangle " << sub << " --help: " << names << ": " << description;
    }
    for (const auto& [option, count] : seen)
      EXPECT_EQ(count, 1) << option << " is listed " << count << " times by untangle " << sub
                          << " --help";
  }
}

// The man page source of one tagged paragraph with its macros and quotes taken out and its lines
// joined: what a reader sees, give or take spaces before punctuation.
std::string plain_text(const std::string& roff) {
  std::string text;
  for (const std::string& line : lines_of(roff)) {
    text += " " + std::regex_replace(line, std::regex(R"(^\.[A-Za-z]+ ?)"), "");
  }
  text = std::regex_replace(text, std::regex("\""), "");
  return std::regex_replace(text, std::regex(R"(\s+)"), " ");
}

// Whether `text` says "(default VALUE" with VALUE complete there ("(default 0" is not in
// "(default 0.05").
bool states_default(const std::string& text, const std::string& value) {
  const std::regex special(R"([.^$|()\\[\]{}*+?])");
  const std::string escaped = std::regex_replace(value, special, R"(\$&)");
  return std::regex_search(text, std::regex(R"(\(default )" + escaped + R"((?![A-Za-z0-9._-]))"));
}

// Every default the help states ("(default X)", or "(default)" for one of a flag pair) is the one
// the man page states for that option of that command: the code's value and the reference agree.
TEST(ManPage, StatesTheDefaultsOfTheHelp) {
  const std::string options = man_section(normalized_man_source(), "OPTIONS");
  ASSERT_FALSE(options.empty());
  // Tagged paragraphs per subsection: (subsection title, tag line, paragraph).
  struct Entry {
    std::string section, tag, text;
  };
  std::vector<Entry> entries;
  std::string section;
  std::istringstream in(options);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind(".SS", 0) == 0) section = lines[i];
    if (lines[i] != ".TP" || i + 1 >= lines.size()) continue;
    Entry e{section, lines[i + 1], ""};
    for (std::size_t j = i + 2; j < lines.size(); ++j) {
      if (lines[j] == ".TP" || lines[j].rfind(".S", 0) == 0) break;
      e.text += lines[j] + "\n";
    }
    entries.push_back(e);
  }
  std::size_t checked = 0;
  for (const auto& [sub, help] : subcommand_helps()) {
    for (const auto& [names, description] : option_lines(help)) {
      std::smatch m;
      if (!std::regex_search(description, m, std::regex(R"(\(default( [^)]*)?\))"))) continue;
      const std::string value = m[1].matched ? m[1].str().substr(1) : "";
      for (const std::string& option : options_in_help(names)) {
        if (option == "-h" || option == "--help") continue;
        ++checked;
        bool stated = false;
        for (const Entry& e : entries) {
          if (!contains_token(e.section, sub) || !contains_token(e.tag, option)) continue;
          const std::string text = plain_text(e.text);
          stated = stated || (value.empty() ? text.find("default") != std::string::npos
                                            : states_default(text, value));
        }
        EXPECT_TRUE(stated) << "untangle " << sub << " --help gives " << option << " the default '"
                            << value << "'; its entry in the man page's OPTIONS does not say so";
      }
    }
  }
  EXPECT_GE(checked, 8u);  // threads, method, max-iterations, clearance, the flag, repeat, ...
}

TEST(ManPage, VersionNamesToolAndLibraries) {
  const RunResult r = run_cli("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.err, "");
  for (const char* name : {"untangle", "CGAL", "assimp", "Eigen"}) {
    const std::regex line(std::string("(^|\n)") + name + R"( [0-9]+(\.[0-9]+)+(\n|$))");
    EXPECT_TRUE(std::regex_search(r.out, line)) << "no '" << name << " X.Y' line in:\n" << r.out;
  }
}

TEST(ManPage, UsageErrorsExitTwoWithOneLine) {
  for (const char* arguments : {"--no-such-option", "", "check --no-such-option x.obj"}) {
    const RunResult r = run_cli(arguments);
    EXPECT_EQ(r.exit_code, 2) << "untangle " << arguments;
    EXPECT_EQ(r.out, "") << "untangle " << arguments;
    const std::vector<std::string> lines = lines_of(r.err);
    EXPECT_EQ(lines.size(), 1u) << "untangle " << arguments << ": stderr is\n" << r.err;
    if (!lines.empty()) {
      EXPECT_FALSE(lines[0].empty()) << "untangle " << arguments;
    }
  }
}

}  // namespace
