// The JSON fast path stays honest: the hand-written tokenizer and RapidJSON give the same tape
// or the same error on every file of every checked-in fuzz corpus (the comparison itself is in
// tests/support/json_tape_differential.hpp, shared with fuzz_json_tape_differential).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "json_codec_tape.hpp"
#include "json_tape_differential.hpp"
#include "ocp/json_codec.hpp"

namespace ocp {
namespace {

namespace fs = std::filesystem;
using json_detail::Tape;
using testing::compare_json_tokenizers;

const fs::path corpus_root = OCP_FUZZ_CORPUS_DIR;

std::string read_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream content;
  content << file.rdbuf();
  return content.str();
}

std::vector<fs::path> files_under(const fs::path& folder) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(JsonTapeDifferential, EveryCorpusFileGivesTheSameTapeOrTheSameError) {
  ASSERT_TRUE(fs::is_directory(corpus_root / "fuzz_json_tape_differential")) << corpus_root;
  std::size_t files = 0;
  std::size_t taken_by_fast_path = 0;
  for (const fs::path& path : files_under(corpus_root)) {
    const auto result = compare_json_tokenizers(read_file(path));
    EXPECT_EQ(result.difference, "") << fs::relative(path, corpus_root);
    ++files;
    taken_by_fast_path += result.fast_path_took ? 1 : 0;
  }
  RecordProperty("files", static_cast<int>(files));
  RecordProperty("taken_by_fast_path", static_cast<int>(taken_by_fast_path));
  // Both paths must actually be exercised, or the comparison proves nothing.
  EXPECT_GE(files, 90u);
  EXPECT_GE(taken_by_fast_path, 20u);
  EXPECT_GE(files - taken_by_fast_path, 50u);
}

// Every corpus document also compares equal when cut short at each byte: most cuts are errors
// on both sides, which must agree in code and detail.
TEST(JsonTapeDifferential, EveryPrefixOfTheDifferentialCorpusAgrees) {
  const std::vector<fs::path> documents = files_under(corpus_root / "fuzz_json_tape_differential");
  EXPECT_GT(documents.size(), 0u) << "an empty corpus: the comparison proved nothing";
  for (const fs::path& path : documents) {
    const std::string document = read_file(path);
    for (std::size_t length = 0; length < document.size() && length < 2048; ++length) {
      const auto result = compare_json_tokenizers(std::string_view(document).substr(0, length));
      ASSERT_EQ(result.difference, "") << path.filename() << " cut at " << length;
    }
  }
}

// The comparer can fail: a tape that differs in any one field, or an outcome that differs in
// acceptance or error, is reported.
TEST(JsonTapeDifferential, TheComparerDetectsADifferentTape) {
  const std::string json = R"({"ack_time": 12, "pos": [1.5, "x", null]})";
  Tape fast;
  Tape reference;
  ASSERT_TRUE(json_detail::tokenize_fast_path(json, fast));
  ASSERT_TRUE(json_detail::tokenize_with_rapidjson(json, reference).ok());
  ASSERT_EQ(testing::tape_difference(fast, reference), "");

  Tape shifted = reference;
  shifted.tokens[3].source_offset += 1;
  EXPECT_NE(testing::tape_difference(fast, shifted).find("source offset"), std::string::npos);

  Tape other_kind = reference;
  other_kind.tokens.back().kind = json_detail::TokenKind::array_end;
  EXPECT_NE(testing::tape_difference(fast, other_kind).find("kind"), std::string::npos);

  Tape other_text = reference;
  other_text.text[other_text.tokens[2].text_begin] = '9';  // the number "12" now reads "92"
  EXPECT_NE(testing::tape_difference(fast, other_text).find("text"), std::string::npos);

  Tape shorter = reference;
  shorter.tokens.pop_back();
  EXPECT_NE(testing::tape_difference(fast, shorter).find("token count"), std::string::npos);

  const Status rejected = json_detail::tokenize_with_rapidjson("{", reference);
  ASSERT_FALSE(rejected.ok());
  EXPECT_NE(testing::outcome_difference(Ok{}, fast, rejected, reference), "");
  const Status too_deep{Error{make_error_code(PeerError::too_deep), rejected.error().detail}};
  EXPECT_NE(testing::outcome_difference(too_deep, fast, rejected, reference).find("different errors"),
            std::string::npos);
}

// The cases where RapidJSON 1.1 alone would be wrong or where the limits bite, pinned down
// (both sides already agree on them through the corpus; these fix what they agree on).
TEST(JsonTapeDifferential, KnownHardCasesHaveTheExpectedOutcome) {
  Tape tape;
  // RapidJSON 1.1 accepts a lone low surrogate escape; the codec must not.
  EXPECT_EQ(json_detail::tokenize(R"({"a":"\udc00"})", tape).error().code, PeerError::malformed_json);
  EXPECT_TRUE(json_detail::tokenize(R"({"a":"\ud83d\ude00"})", tape).ok());
  const std::string at_limit = std::string(max_json_depth, '[') + std::string(max_json_depth, ']');
  const std::string beyond = "[" + at_limit + "]";
  EXPECT_TRUE(json_detail::tokenize(at_limit, tape, false).ok());
  EXPECT_EQ(json_detail::tokenize(beyond, tape, false).error().code, PeerError::too_deep);
  EXPECT_FALSE(json_detail::tokenize_fast_path(beyond, tape));
  EXPECT_EQ(json_detail::tokenize(R"({"n":1e400})", tape).error().code, PeerError::malformed_json);
  EXPECT_EQ(json_detail::tokenize("\xef\xbb\xbf{}", tape).error().code, PeerError::malformed_json);
  // A string cut off inside a 4-byte UTF-8 sequence at the very end: the validating decoder
  // once wrote the bytes it read past the end beyond the work copy (found by the differential
  // fuzz target; AddressSanitizer sees it at this size, where the copy fills its allocation).
  const std::string truncated = "{\"" + std::string(120, 'p') + "\xf0\x9f";
  EXPECT_EQ(json_detail::tokenize(truncated, tape).error().code, PeerError::malformed_json);
  // -0 and integers past u64 are valid JSON: kept as their source text.
  ASSERT_TRUE(json_detail::tokenize(R"({"n":-0,"m":18446744073709551616})", tape).ok());
  EXPECT_EQ(tape.text_of(tape.tokens[2]), "-0");
  EXPECT_EQ(tape.text_of(tape.tokens[4]), "18446744073709551616");
}

}  // namespace
}  // namespace ocp
