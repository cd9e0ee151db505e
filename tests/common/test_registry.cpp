// PluginKind and Registrar (common/registry.hpp): a kind's entries by name, its checks at registration, and the
// catalogue of kinds that `semlb list` reads.
#include <gtest/gtest.h>

#include <algorithm>

#include "common/registry.hpp"

namespace semlb {
namespace {

// A kind of this test only: its names must be C identifiers (as the engine's plug-ins with generated code).
struct Widget {
  static constexpr const char* kKind = "widget";
  static constexpr const char* kListed = "test-widgets";
  int size = 0;
  static void registering(const std::string& name, const Widget&) { check_plugin_name(kKind, name); }
};
using Widgets = PluginKind<Widget>;

// A kind without a check.
struct Gadget {
  static constexpr const char* kKind = "gadget";
  static constexpr const char* kListed = "test-gadgets";
  std::string what;
};

const Registrar<Widget> small("small", {1});
const Registrar<Widget> large("large", {3});
const Registrar<Gadget> any("any name-at.all", {"x"});

TEST(Registry, AKindFindsItsEntriesByNameInNameOrder) {
  EXPECT_EQ(Widgets::names(), (std::vector<std::string>{"large", "small"}));
  EXPECT_EQ(Widgets::at("small").size, 1);
  EXPECT_EQ(Widgets::find("medium"), nullptr);
  EXPECT_EQ(Widgets::index("large"), 0);
  EXPECT_EQ(Widgets::index("small"), 1);
  EXPECT_EQ(Widgets::index("medium"), -1);
  EXPECT_EQ(Widgets::known(), "large, small");
  try {
    Widgets::at("medium");
    ADD_FAILURE() << "no throw";
  } catch (const std::logic_error& e) {
    EXPECT_STREQ(e.what(), "no widget 'medium' (known: large, small)");
  }
  EXPECT_EQ(PluginKind<Gadget>::at("any name-at.all").what, "x");  // no check: any name
}

TEST(Registry, TheKindsChecksRunBeforeAnEntryIsAdded) {
  EXPECT_THROW(Registrar<Widget>("not-an-identifier", {2}), std::logic_error);
  EXPECT_EQ(Widgets::find("not-an-identifier"), nullptr);
  EXPECT_THROW(Registrar<Widget>("small", {2}), std::logic_error);  // registered twice
  EXPECT_EQ(Widgets::at("small").size, 1);
}

TEST(Registry, EveryKindIsInTheCatalogueOfListedKinds) {
  const auto kinds = listed_kinds().names();
  for (const char* k : {"test-widgets", "test-gadgets"}) {
    ASSERT_NE(std::find(kinds.begin(), kinds.end(), k), kinds.end()) << k;
  }
  EXPECT_EQ((*listed_kinds().find("test-widgets"))(), Widgets::names());
}

}  // namespace
}  // namespace semlb
