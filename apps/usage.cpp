#include "apps/usage.h"

#include <algorithm>
#include <cstdio>

namespace prism {
namespace {

// Optimal string alignment distance: a swapped pair of letters ("--sdp") is one edit, as
// it is one slip of the fingers.
size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::vector<size_t>> d(a.size() + 1, std::vector<size_t>(b.size() + 1));
  for (size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (size_t i = 1; i <= a.size(); ++i)
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  return d[a.size()][b.size()];
}

std::string command_list(const CLI::App& app) {
  std::string list;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    list += (list.empty() ? "" : ", ") + sub->get_name();
  return list;
}

const CLI::App* find_command(const CLI::App& app, const std::string& name) {
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    if (sub->get_name() == name) return sub;
  return nullptr;
}

std::vector<std::string> command_names(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  return names;
}

std::string unknown_command(const CLI::App& app, const std::string& word) {
  const std::string near = nearest_name(word, command_names(app));
  return "unknown command '" + word + "'" + (near.empty() ? "" : "; did you mean " + near + "?") +
         " (commands: " + command_list(app) + ")";
}

}  // namespace

std::string nearest_name(const std::string& word, const std::vector<std::string>& names) {
  // Of names equally near, the one sharing the longest start with the word: "--sp" is
  // one edit from both "--spp" and "--up", and means the first.
  const auto shared_start = [&](const std::string& name) {
    return std::mismatch(word.begin(), word.end(), name.begin(), name.end()).first - word.begin();
  };
  std::string best;
  size_t best_distance = 0;
  for (const std::string& name : names) {
    const size_t d = edit_distance(word, name);
    if (best.empty() || d < best_distance ||
        (d == best_distance && shared_start(name) > shared_start(best))) {
      best = name;
      best_distance = d;
    }
  }
  // A third of the word (dashes aside) may be wrong, and at least two letters: "--sp" is
  // "--spp", "--integrators" is "--integrator", but "--foo" is nothing.
  const size_t letters = word.size() - std::min(word.find_first_not_of('-'), word.size());
  const size_t allowed = std::max<size_t>(2, letters / 3);
  return !best.empty() && best_distance <= allowed && best_distance < letters ? best : "";
}

std::vector<std::string> option_names(const CLI::App& cmd) {
  std::vector<std::string> names;
  for (const CLI::Option* option : cmd.get_options()) {
    for (const std::string& n : option->get_lnames()) names.push_back("--" + n);
    for (const std::string& n : option->get_snames()) names.push_back("-" + n);
  }
  return names;
}

std::string describe_parse_error(const CLI::App& app, const CLI::ParseError& error) {
  const auto subcommands = app.get_subcommands([](const CLI::App*) { return true; });
  if (dynamic_cast<const CLI::RequiredError*>(&error) && app.get_subcommands().empty()) {
    const std::vector<std::string> left = app.remaining(false);
    if (!left.empty() && left.front().rfind("-", 0) != 0) return unknown_command(app, left.front());
    if (left.empty()) return "a command is required: " + command_list(app);
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&error)) {
    for (const CLI::App* sub : subcommands) {
      for (const std::string& word : sub->remaining(false)) {
        if (word.size() < 2 || word[0] != '-' || (word[1] >= '0' && word[1] <= '9')) continue;
        const std::string name = word.substr(0, word.find('='));
        const std::string near = nearest_name(name, option_names(*sub));
        return sub->get_name() + ": unknown option " + name +
               (near.empty() ? "" : "; did you mean " + near + "?");
      }
    }
    const std::vector<std::string> left = app.remaining(false);
    if (app.get_subcommands().empty() && !left.empty() && left.front().rfind("-", 0) != 0)
      return unknown_command(app, left.front());
  }
  return error.what();
}

CLI::App* add_help_command(CLI::App& app, std::string* command) {
  CLI::App* cmd = app.add_subcommand("help", "Print the help of prism or of one command");
  cmd->add_option("command", *command, "A command: its options and what they do");
  return cmd;
}

int run_help(const CLI::App& app, const std::string& command) {
  if (command.empty()) {
    // Not app.help(): it would describe the command parsed, `help` itself.
    std::fputs(
        app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal).c_str(),
        stdout);
    return 0;
  }
  const CLI::App* sub = find_command(app, command);
  if (!sub) {
    std::fprintf(stderr, "prism: error: help: %s\n", unknown_command(app, command).c_str());
    return 2;
  }
  std::fputs(sub->help(app.get_name()).c_str(), stdout);
  return 0;
}

}  // namespace prism
