#pragma once
// Helpers shared by the codec tests: seed vectors from tests/data and text surgery on JSON.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <string_view>

#include "ocp/error.hpp"

namespace ocp::test {

inline std::string read_data_file(const std::string& relative_path) {
  std::ifstream file(std::string(OCP_TEST_DATA_DIR) + "/" + relative_path, std::ios::binary);
  EXPECT_TRUE(file.good()) << "cannot open " << relative_path;
  std::ostringstream content;
  content << file.rdbuf();
  return content.str();
}

// Replaces the first occurrence of `from` (which must occur) by `to`.
inline std::string replace_once(std::string text, std::string_view from, std::string_view to) {
  const std::size_t position = text.find(from);
  EXPECT_NE(position, std::string::npos) << "'" << from << "' not in " << text;
  if (position != std::string::npos) text.replace(position, from.size(), to);
  return text;
}

// `"key":` — built piecewise: GCC 12 warns falsely (-Wrestrict) on "\"" + std::string + "\"".
inline std::string member_prefix(std::string_view key) {
  std::string pattern(1, '"');
  pattern.append(key);
  pattern.append("\":");
  return pattern;
}

// End of the JSON value starting at `begin` (strings in test texts hold no brackets).
inline std::size_t value_end(const std::string& text, std::size_t begin) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = begin; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') in_string = true;
    else if (c == '{' || c == '[') ++depth;
    else if (c == '}' || c == ']') {
      if (depth == 0) return i;
      --depth;
    } else if (c == ',' && depth == 0) {
      return i;
    }
  }
  return text.size();
}

// Replaces the value of the first member named `key` in compact JSON.
inline std::string set_member(std::string text, std::string_view key, std::string_view value) {
  const std::string pattern = member_prefix(key);
  const std::size_t position = text.find(pattern);
  EXPECT_NE(position, std::string::npos) << pattern << " not in " << text;
  if (position == std::string::npos) return text;
  const std::size_t begin = position + pattern.size();
  text.replace(begin, value_end(text, begin) - begin, value);
  return text;
}

// Removes the first member named `key` (and one adjacent comma) from compact JSON.
inline std::string remove_member(std::string text, std::string_view key) {
  const std::string pattern = member_prefix(key);
  std::size_t begin = text.find(pattern);
  EXPECT_NE(begin, std::string::npos) << pattern << " not in " << text;
  if (begin == std::string::npos) return text;
  std::size_t end = value_end(text, begin + pattern.size());
  if (end < text.size() && text[end] == ',') {
    ++end;
  } else if (begin > 0 && text[begin - 1] == ',') {
    --begin;
  }
  text.erase(begin, end - begin);
  return text;
}

template <class T>
::testing::AssertionResult fails_with(const Result<T>& result, PeerError code,
                                      std::string_view detail) {
  if (result.ok()) return ::testing::AssertionFailure() << "decoded, expected an error";
  if (result.error().code != make_error_code(code) || result.error().detail != detail) {
    return ::testing::AssertionFailure()
           << "got " << result.error().message() << "; expected "
           << make_error_code(code).message() << ": " << detail;
  }
  return ::testing::AssertionSuccess();
}

template <class T>
::testing::AssertionResult fails_with_code(const Result<T>& result, PeerError code) {
  if (result.ok()) return ::testing::AssertionFailure() << "decoded, expected an error";
  if (result.error().code != make_error_code(code)) {
    return ::testing::AssertionFailure() << "got " << result.error().message();
  }
  if (result.error().detail.empty()) return ::testing::AssertionFailure() << "empty detail";
  return ::testing::AssertionSuccess();
}

}  // namespace ocp::test
