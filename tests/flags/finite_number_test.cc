// Numeric flags refuse NaN and infinities, whichever subcommand they belong to and whatever other
// checks they carry (CLI11's Range lets NaN through).
#include "libs/flags/finite_number.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

namespace haptex::flags {
namespace {

struct Flags {
  double duration_s = 1;
  std::vector<double> gains;
  int count = 0;
  std::uint64_t seed = 0;
  std::string name;
  double rate_hz = 5;
};

// An app like haptex's: options at the top, in a subcommand and in a nested one, added before the
// check is applied.
void Build(CLI::App& app, Flags& f) {
  app.add_option("--duration", f.duration_s)->check(CLI::Range(0.0, 1e7));
  app.add_option("--gains", f.gains);
  app.add_option("--count", f.count);
  app.add_option("--seed", f.seed);
  app.add_option("--name", f.name);
  CLI::App* run = app.add_subcommand("run");
  CLI::App* fast = run->add_subcommand("fast");
  fast->add_option("--rate", f.rate_hz)->check(CLI::Range(100.0, 20000.0));
  RefuseNonFiniteNumbers(app);
}

// "" when accepted, else CLI11's message.
std::string Parse(std::vector<std::string> args) {
  CLI::App app{"test", "test"};
  Flags f;
  Build(app, f);
  std::reverse(args.begin(), args.end());  // CLI11 takes them in reverse
  try {
    app.parse(args);
  } catch (const CLI::ValidationError& e) {
    return e.what();
  } catch (const CLI::ParseError& e) {
    return std::string("parse error: ") + e.what();
  }
  return "";
}

TEST(FiniteNumberTest, NanAndInfinitiesAreRefusedEverywhere) {
  for (const std::string value : {"nan", "NaN", "-nan", "nan(0x1)", "inf", "-inf", "Infinity", "1e999", "-1e400"}) {
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"--duration=" + value}, {"--gains=1", "--gains=" + value}, {"run", "fast", "--rate=" + value}}) {
      // refused as such; where a range comes first it may say "not in range" for an infinity
      const std::string error = Parse(args);
      EXPECT_NE(error.find(value), std::string::npos) << args.back() << ": " << error;
      EXPECT_EQ(error.find("parse error"), std::string::npos) << args.back() << ": " << error;
    }
    // NaN passes every range: this check is what refuses it
    if (value.find("nan") != std::string::npos || value.find("NaN") != std::string::npos) {
      EXPECT_NE(Parse({"--duration=" + value}).find("is not a finite number"), std::string::npos);
      EXPECT_NE(Parse({"run", "fast", "--rate=" + value}).find("is not a finite number"), std::string::npos);
    }
    // integers never read such text, and say so in their own words
    EXPECT_FALSE(Parse({"--count=" + value}).empty()) << value;
    EXPECT_FALSE(Parse({"--seed=" + value}).empty()) << value;
  }
  EXPECT_EQ(Parse({"--gains=inf"}), "--gains: 'inf' is not a finite number");
}

TEST(FiniteNumberTest, FiniteNumbersAndTextPass) {
  EXPECT_EQ(Parse({"--duration", "2.5"}), "");
  EXPECT_EQ(Parse({"--duration", "0"}), "");
  EXPECT_EQ(Parse({"--gains", "1e-300", "-1e300"}), "");
  EXPECT_EQ(Parse({"run", "fast", "--rate", "5000"}), "");
  EXPECT_EQ(Parse({"--count", "-3"}), "");
  EXPECT_EQ(Parse({"--name", "nan"}), "") << "text options are not numbers";
  EXPECT_NE(Parse({"--duration", "soon"}), "") << "no number at all: the conversion refuses it";
  EXPECT_NE(Parse({"run", "fast", "--rate", "50"}), "") << "the option's own range still applies";
}

TEST(FiniteNumberTest, TheValidatorAlone) {
  const CLI::Validator check = FiniteNumber();
  std::string value = "nan";
  EXPECT_EQ(check(value), "'nan' is not a finite number");
  value = "42";
  EXPECT_EQ(check(value), "");
}

}  // namespace
}  // namespace haptex::flags
