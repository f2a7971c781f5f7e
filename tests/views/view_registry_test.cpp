// The view registry: every view has a unique name and a title, is found by
// its name, and on an empty log says why it cannot be shown.
#include <gtest/gtest.h>

#include <set>

#include "core/log/log.h"
#include "views/view.h"

using namespace roverlab;

TEST(ViewRegistry, NamesAreUniqueAndFound) {
  const auto& views = views::all_views();
  ASSERT_GE(views.size(), 4u);
  std::set<std::string> names, titles;
  for (const auto& v : views) {
    EXPECT_FALSE(v->name().empty());
    EXPECT_FALSE(v->title().empty());
    EXPECT_TRUE(names.insert(v->name()).second) << v->name();
    EXPECT_TRUE(titles.insert(v->title()).second) << v->title();
    EXPECT_EQ(views::find_view(v->name()), v.get());
    EXPECT_NE(views::view_names().find(v->name()), std::string::npos);
  }
  EXPECT_EQ(views::find_view("spaceship"), nullptr);
}

TEST(ViewRegistry, EveryViewSaysWhyItCannotShowAnEmptyLog) {
  const log::Log empty;
  views::SceneInput in;
  in.log = &empty;
  for (const auto& v : views::all_views()) EXPECT_NE(v->needs(in), "") << v->name();
}
