#pragma once
// When a command line does not parse, name the word that is wrong. CLI11 blames what follows a
// typo: `--case vehicle/2/2 -- node c.js` gives "The following arguments were not expected:
// … c.js node", and `vehicl` gives "A subcommand is required". We walk the words as CLI11 would
// (subcommands descend, `--` ends the options) and report the first unknown option or command,
// with the nearest known name when one is close ("did you mean '--cases'?").
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <optional>
#include <string>
#include <vector>

namespace ocp::cli {

// Edit distance (insert, delete, substitute) between two short words.
inline std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

// The candidate nearest to `word`, if it is near enough to be a typo of it (a third of its
// letters, at least 2), or one starts with the other ("--dur" for "--duration-s").
inline std::optional<std::string> nearest(const std::string& word, const std::vector<std::string>& candidates) {
  std::optional<std::string> best;
  std::size_t best_distance = std::max<std::size_t>(2, word.size() / 3) + 1;
  for (const std::string& candidate : candidates) {
    std::size_t distance = edit_distance(word, candidate);
    const bool prefix = word.size() >= 4 && (candidate.rfind(word, 0) == 0 || word.rfind(candidate, 0) == 0);
    if (prefix) distance = std::min<std::size_t>(distance, 1);
    if (distance < best_distance) {
      best_distance = distance;
      best = candidate;
    }
  }
  return best;
}

namespace detail {

inline std::vector<CLI::App*> subcommands_of(CLI::App& app) {
  return app.get_subcommands([](CLI::App*) { return true; });
}

inline CLI::App* subcommand_named(CLI::App& app, const std::string& word) {
  for (CLI::App* sub : subcommands_of(app)) {
    if (sub->check_name(word)) return sub;
  }
  return nullptr;
}

// The option `word` names in `chain` (the app and the subcommands entered), or nullptr.
inline const CLI::Option* option_named(const std::vector<CLI::App*>& chain, const std::string& word) {
  for (const CLI::App* app : chain) {
    if (const CLI::Option* option = app->get_option_no_throw(word)) return option;
  }
  return nullptr;
}

inline std::vector<std::string> option_names(const std::vector<CLI::App*>& chain) {
  std::vector<std::string> names;
  for (const CLI::App* app : chain) {
    for (const CLI::Option* option : app->get_options()) {
      for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    }
  }
  return names;
}

inline bool looks_like_number(const std::string& word) {
  return word.size() > 1 && word[0] == '-' && (std::isdigit(static_cast<unsigned char>(word[1])) || word[1] == '.');
}

inline bool takes_positionals(CLI::App& app) {
  return !app.get_options([](const CLI::Option* o) { return o->get_lnames().empty() && o->get_snames().empty(); }).empty();
}

inline std::string command_path(const std::vector<CLI::App*>& chain) {
  std::string path;
  for (const CLI::App* app : chain) path += (path.empty() ? "" : " ") + app->get_name();
  return path;
}

}  // namespace detail

// "unknown option '--case' for 'ocp_conformance vehicle'; did you mean '--cases'?", or nullopt
// when every word before `--` is known (then CLI11's own message is the right one).
inline std::optional<std::string> unknown_word(CLI::App& app, int argc, const char* const* argv) {
  std::vector<CLI::App*> chain{&app};
  bool expects_value = false;
  bool positional_seen = false;
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    if (word == "--") break;
    if (expects_value) {   // the option's value, whatever it looks like ("-inf" included)
      expects_value = false;
      continue;
    }
    if (word.size() > 1 && word[0] == '-' && !detail::looks_like_number(word)) {
      const std::string name = word.substr(0, word.find('='));
      const std::string lookup = (name.size() > 2 && name[1] != '-') ? name.substr(0, 2) : name;   // -j2
      const CLI::Option* option = detail::option_named(chain, lookup);
      if (option == nullptr) {
        std::string message = "unknown option '" + name + "' for '" + detail::command_path(chain) + "'";
        if (const auto guess = nearest(name, detail::option_names(chain))) message += "; did you mean '" + *guess + "'?";
        return message;
      }
      expects_value = option->get_type_size() != 0 && name == word && lookup == name;
      continue;
    }
    if (CLI::App* sub = detail::subcommand_named(*chain.back(), word)) {
      chain.push_back(sub);
      continue;
    }
    const std::vector<CLI::App*> subs = detail::subcommands_of(*chain.back());
    if (!subs.empty() && !positional_seen && !detail::takes_positionals(*chain.back())) {
      std::vector<std::string> names;
      for (const CLI::App* sub : subs) names.push_back(sub->get_name());
      std::string message = "unknown command '" + word + "' for '" + detail::command_path(chain) + "'";
      if (const auto guess = nearest(word, names)) message += "; did you mean '" + *guess + "'?";
      std::string list;
      for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
      return message + " (commands: " + list + ")";
    }
    positional_seen = true;
  }
  return std::nullopt;
}

}  // namespace ocp::cli
