// The one settings reader: typed reads with ranges, the error prefix of files and flags, unread keys.
#include <gtest/gtest.h>

#include "common/errors.hpp"
#include "common/settings.hpp"

using namespace semlb;

namespace {

// The message of the InputError `f` throws ("" if none).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

Settings sample() {
  Settings s("time", Origin{"s.yaml", 4, "", ""});
  s.set("dt", "0.01", Origin{"s.yaml", 5, "", ""});
  s.set("steps", "2.0", Origin{"s.yaml", 6, "", ""});
  s.set("name", "run", Origin{"", 0, "--set time.name", ""});
  s.set("on", "yes", Origin{"", 0, "--set time", "time"});
  s.set("axes", Settings::Value{Settings::Kind::list, "", {"a", "b"}, Origin{"s.yaml", 8, "", ""}});
  return s;
}

}  // namespace

TEST(Settings, WhereNamesTheFileLineAndFieldOrTheFlag) {
  EXPECT_EQ(where(Origin{"s.yaml", 3, "", ""}, "a.b"), "s.yaml:3: field 'a.b': ");
  EXPECT_EQ(where(Origin{"s.yaml", 0, "", ""}, "a"), "s.yaml: field 'a': ");
  EXPECT_EQ(where(Origin{"", 0, "--ranks", ""}, "ranks"), "--ranks: ");
  EXPECT_EQ(where(Origin{"", 0, "--set a", "a"}, "a"), "--set a: ");
  EXPECT_EQ(where(Origin{"", 0, "--set a", "a"}, "a.b"), "--set a: field 'a.b': ");
  const Settings s = sample();
  EXPECT_EQ(s.where("dt"), "s.yaml:5: field 'time.dt': ");
  EXPECT_EQ(s.where("missing"), "s.yaml:4: field 'time.missing': ");  // an unset key: the fallback
  EXPECT_EQ(s.where(""), "s.yaml:4: field 'time': ");
  EXPECT_EQ(s.where("on"), "--set time: field 'time.on': ");
}

TEST(Settings, TypedReadsAreStrictAndRanged) {
  const Settings s = sample();
  EXPECT_EQ(s.real("dt", 1, 0, 1), 0.01);
  EXPECT_EQ(s.real("absent", 7, 0, 1), 7);  // the fallback is not range-checked
  EXPECT_EQ(error_of([&] { s.real("dt", 1, 0.5, 1); }), "s.yaml:5: field 'time.dt': '0.01' is outside [0.5, 1]");
  EXPECT_EQ(error_of([&] { s.real("dt", 1, 0.01, 1, true); }),
            "s.yaml:5: field 'time.dt': '0.01' is outside (0.01, 1]");
  EXPECT_EQ(error_of([&] { s.integer("steps", 1, 0, 10); }),
            "s.yaml:6: field 'time.steps': '2.0' is not an integer (write integers without '.' or exponent)");
  EXPECT_EQ(error_of([&] { s.real("name", 1); }), "--set time.name: 'run' is not a number");
  EXPECT_EQ(s.text("name", ""), "run");
  EXPECT_EQ(error_of([&] { s.boolean("on", false); }), "--set time: field 'time.on': must be true or false, got 'yes'");
  EXPECT_EQ(s.texts("axes", {}), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(s.texts("name", {}), (std::vector<std::string>{"run"}));
  EXPECT_EQ(error_of([&] { s.text("axes", ""); }), "s.yaml:8: field 'time.axes': must be a single value");
  EXPECT_EQ(error_of([&] { s.integer("axes", 0); }), "s.yaml:8: field 'time.axes': must be an integer");
}

TEST(Settings, FinishRefusesTheFirstUnreadKeyAndSetReplacesInPlace) {
  Settings s = sample();
  s.text("dt", "");
  s.mark_read("steps");
  EXPECT_EQ(s.unread(), (std::vector<std::string>{"name", "on", "axes"}));
  EXPECT_EQ(error_of([&] { s.finish(); }), "--set time.name: unknown setting");
  s.set("dt", "0.5", Origin{"", 0, "--set time.dt", ""});
  EXPECT_EQ(s.keys(), (std::vector<std::string>{"dt", "steps", "name", "on", "axes"}));
  EXPECT_EQ(s.real("dt", 0), 0.5);
  for (const auto& k : s.keys()) s.mark_read(k);
  EXPECT_EQ(error_of([&] { s.finish("unknown training setting"); }), "");
}
