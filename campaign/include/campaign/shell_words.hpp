#pragma once
// Shell words, for the command lines a campaign writes (the sbatch script, repro commands) and
// reads (--client): one quoting rule and one reading of the first word.
#include <string>

namespace ocp::campaign {

// One shell word: 'text', with every ' written as '\''.
inline std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (const char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The first word of a shell command line, its quotes taken off ('a b' and "a b" are one word).
inline std::string first_shell_word(const std::string& command) {
  std::string word;
  char quote = 0;
  for (std::size_t at = command.find_first_not_of(" \t"); at < command.size(); ++at) {
    const char c = command[at];
    if (quote != 0) {
      if (c == quote) {
        quote = 0;
      } else {
        word += c;
      }
    } else if (c == '\'' || c == '"') {
      quote = c;
    } else if (c == ' ' || c == '\t') {
      break;
    } else {
      word += c;
    }
  }
  return word;
}

}  // namespace ocp::campaign
