// Turning CLI11's parse errors into messages that help: an unknown command or option named,
// with the nearest of the command's own names ("did you mean --spp?"), and `prism help
// [COMMAND]`.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

namespace prism {

// The name in `names` nearest to `word` by edit distance (insertions, deletions,
// substitutions, transpositions), or "" when none is near enough to be a likely typo.
std::string nearest_name(const std::string& word, const std::vector<std::string>& names);

// Every spelling of `cmd`'s options: "--spp", "-o", "--output", ...
std::vector<std::string> option_names(const CLI::App& cmd);

// One line for a parse error of `app` (the prism command), without "prism: error: ": an
// unknown command or option with a suggestion, else CLI11's own message.
std::string describe_parse_error(const CLI::App& app, const CLI::ParseError& error);

// Adds `help [COMMAND]` to `app`; `command` is filled when it is parsed.
CLI::App* add_help_command(CLI::App& app, std::string* command);

// Prints the help of `app` or of its subcommand `command` to stdout; 0, or 2 with one line
// on stderr for a command that does not exist.
int run_help(const CLI::App& app, const std::string& command);

}  // namespace prism
