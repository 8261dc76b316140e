// Tests of Result<T> / Status (globe/Result.h): forwarding a failure to another Result type.
#include <atmoglobe/globe/Result.h>

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace atmoglobe {
namespace {

Result<int> parsePositive(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
    return makeError("'" + text + "': not a positive integer");
  }
  return std::stoi(text);
}

// A function with another value type forwards the inner failure unchanged.
Result<std::vector<int>> parseTwo(const std::string& a, const std::string& b) {
  auto first = parsePositive(a);
  if (!first) return first.forwardError();
  auto second = parsePositive(b);
  if (!second) return std::move(second).forwardError();
  return std::vector<int>{*first, *second};
}

// Forwarding into Status and into Result<std::string> (where the value type is also built
// from a string, so an accidental conversion would turn the error into a value).
Status checkPositive(const std::string& text) {
  auto v = parsePositive(text);
  if (!v) return v.forwardError();
  return Ok{};
}
Result<std::string> describe(const std::string& text) {
  const Result<int> v = parsePositive(text);  // const: forwarding copies
  if (!v) return v.forwardError();
  return "value " + std::to_string(*v);
}

TEST(Result, ForwardErrorKeepsTheMessageByteForByte) {
  const std::string odd = "bad\tvalue: \xc3\xa9 \"quoted\"\n";  // tab, UTF-8, quotes, newline
  auto r = parseTwo("12", odd);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error(), "'" + odd + "': not a positive integer");

  auto first = parseTwo("x", "7");
  ASSERT_FALSE(first);
  EXPECT_EQ(first.error(), "'x': not a positive integer");  // the first failure wins
}

TEST(Result, ForwardErrorIntoStatusAndStringResult) {
  const Status s = checkPositive("-3");
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.error(), "'-3': not a positive integer");

  const Result<std::string> d = describe("4x");
  ASSERT_FALSE(d.ok());  // an error, not a value holding the message
  EXPECT_EQ(d.error(), "'4x': not a positive integer");
}

TEST(Result, ValuesPassThroughWhenNothingFails) {
  auto r = parseTwo("12", "345");
  ASSERT_TRUE(r.ok());
  EXPECT_EQ(*r, (std::vector<int>{12, 345}));
  EXPECT_TRUE(checkPositive("9").ok());
  ASSERT_TRUE(describe("42").ok());
  EXPECT_EQ(*describe("42"), "value 42");
}

TEST(Result, ForwardErrorFromLvalueLeavesTheSourceIntact) {
  Result<std::unique_ptr<int>> failed = makeError("no such file");
  const Error copy = failed.forwardError();
  EXPECT_EQ(copy.message, "no such file");
  ASSERT_FALSE(failed.ok());
  EXPECT_EQ(failed.error(), "no such file");  // still there: an lvalue is copied, not moved from
  const Error moved = std::move(failed).forwardError();
  EXPECT_EQ(moved.message, "no such file");
}

}  // namespace
}  // namespace atmoglobe
