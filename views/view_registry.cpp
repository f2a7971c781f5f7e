#include "views/view.h"

namespace roverlab::views {

#define ROVERLAB_VIEW(id) std::unique_ptr<View> make_##id##_view();
#include "views/views.def"
#undef ROVERLAB_VIEW

std::unique_ptr<Scene> View::build(const SceneInput& input) const {
  std::unique_ptr<Scene> scene = make_scene(input);
  if (scene->follows_time()) scene->set_time(input.time.value_or(scene->default_time()));
  return scene;
}

bool View::reset(Scene& scene, const SceneInput& input) const {
  if (!reset_scene(scene, input)) return false;
  if (scene.follows_time()) scene.set_time(input.time.value_or(scene.default_time()));
  return true;
}

const std::vector<std::unique_ptr<View>>& all_views() {
  static const std::vector<std::unique_ptr<View>> views = [] {
    std::vector<std::unique_ptr<View>> v;
#define ROVERLAB_VIEW(id) v.push_back(make_##id##_view());
#include "views/views.def"
#undef ROVERLAB_VIEW
    return v;
  }();
  return views;
}

const View* find_view(const std::string& name) {
  for (const auto& v : all_views()) {
    if (v->name() == name) return v.get();
  }
  return nullptr;
}

std::string view_names(const std::string& separator, const std::string& last_separator) {
  std::string out;
  const auto& views = all_views();
  for (std::size_t i = 0; i < views.size(); ++i) {
    if (i > 0) out += i + 1 == views.size() ? last_separator : separator;
    out += views[i]->name();
  }
  return out;
}

}  // namespace roverlab::views
