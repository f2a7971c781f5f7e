#pragma once
// The view registry: every view of a log RoverLab draws (the `render`
// command, the report's images, the GUI's tabs) is one View, listed once in
// views/views.def. A View says what it needs from the log and builds a
// Scene; a Scene attaches to a render window and follows the timeline.
//
// Adding a view: define `std::unique_ptr<View> make_<id>_view()` in the
// scene's own .cpp and add `ROVERLAB_VIEW(<id>)` to views/views.def.

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/kinematics/rover_model.h"
#include "core/log/log.h"
#include "core/models/skid_steer_odometry.h"
#include "views/panel_figure.h"
#include "views/traction_surface_scene.h"

class vtkRenderWindow;

namespace roverlab::views {

// One plotted channel.
struct ChannelRef {
  std::string stream, channel;
};

// What a view is built from. The app fills what the view uses.
struct SceneInput {
  const log::Log* log = nullptr;                      // null only for views that use_surface_data()
  std::optional<TractionSurfaceData> surface;         // views that use_surface_data(): built by the app
  std::vector<ChannelRef> channels;                   // plotted channels; empty: the view's default
  estimation::SkidSteerGeometry rover;                // the rover drawn (skid-steer views)
  std::optional<kinematics::RoverModel> articulated;  // the rover drawn when it has a DH description
  std::optional<double> time;                         // shown first; default: the scene's default_time()
  std::vector<std::pair<std::string, const log::Log*>>
      compared;                   // other runs against `log` (name, log): compares_runs()
  std::optional<LabFigures> lab;  // views that use_lab_figures(): built by the app
};

// A built view: its renderers (or context view) attach to a render window;
// set_time follows the timeline.
class Scene {
 public:
  virtual ~Scene() = default;
  Scene() = default;
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  // Adds the scene's renderers to `window` (or draws its context view in it).
  virtual void attach(vtkRenderWindow* window) = 0;
  virtual void detach(vtkRenderWindow* window) = 0;
  // Lays the scene out for a window `pixels` wide (charts decimate to it).
  virtual void fit_width(int /*pixels*/) {}
  // False when the scene does not change with time (set_time does nothing).
  virtual bool follows_time() const { return true; }
  virtual void set_time(double t) = 0;
  virtual double start_time() const = 0;
  virtual double end_time() const = 0;
  // The time shown when none is asked for: the middle of the drive.
  virtual double default_time() const { return 0.5 * (start_time() + end_time()); }
  // What the log lacks for this view, one sentence each.
  virtual std::vector<std::string> notes() const { return {}; }
};

class View {
 public:
  virtual ~View() = default;
  // The name on the command line (`render --view NAME`).
  virtual std::string name() const = 0;
  // The GUI tab's title.
  virtual std::string title() const = 0;
  // What the picture shows, as the report's heading (default: the title).
  virtual std::string heading() const { return title(); }
  // Empty when the view can be built from `input`, else why not (one line).
  virtual std::string needs(const SceneInput& input) const = 0;
  // Builds the scene at the input's time. Call only when needs() is empty.
  std::unique_ptr<Scene> build(const SceneInput& input) const;
  // True when reset() shows another input in a scene this view built, with
  // the scene's own VTK objects: a GUI then keeps the scene for its widget's
  // lifetime (a chart's interactor style holds timers that must not outlive it).
  virtual bool resets_scene() const { return false; }
  // Shows `input` in `scene` (built by this view) at the input's time; false
  // when the view cannot (build a new scene). Call only when needs() is empty.
  bool reset(Scene& scene, const SceneInput& input) const;
  // True when the view draws SceneInput::surface rather than the log.
  virtual bool uses_surface_data() const { return false; }
  // True when the view draws SceneInput::compared against the log (`render --compare`).
  virtual bool compares_runs() const { return false; }
  // True when the view draws one of SceneInput::lab's figures (a lab test file, not a log).
  virtual bool uses_lab_figures() const { return false; }
  // True when the view plots SceneInput::channels.
  virtual bool uses_channels() const { return false; }
  // True when the view plots one channel against another: SceneInput::channels
  // holds x then y (`render --x --y`); the report has no pair to choose and leaves it out.
  virtual bool plots_channel_pair() const { return false; }
  // The estimate streams it draws (name prefixes, e.g. "estimate/ins/"): the
  // app runs, before building it, the analyses that add one of them and can
  // run (app::AnalysisIdentity::estimate_streams), and no other.
  virtual std::vector<std::string> estimates_drawn() const { return {}; }
  // What the log lacks that no analysis can add (its measured streams),
  // checked before any analysis runs: empty when the view may be fed.
  virtual std::string needs_before_estimates(const log::Log& log) const {
    (void)log;
    return {};
  }
  // The report's image height for this view, as a fraction of a scene's
  // (charts are drawn wide and low).
  virtual double report_height() const { return 1.0; }
  // True when the GUI turns the camera as a trackball (3D scenes).
  virtual bool trackball_camera() const { return false; }
  // True when the GUI only pans and zooms, never turns the camera (maps: north stays up).
  virtual bool top_down_camera() const { return false; }

 protected:
  virtual std::unique_ptr<Scene> make_scene(const SceneInput& input) const = 0;
  // Shows `input` in `scene`; views whose resets_scene() is true implement it.
  virtual bool reset_scene(Scene& /*scene*/, const SceneInput& /*input*/) const { return false; }
};

// Every view, in the order of views/views.def.
const std::vector<std::unique_ptr<View>>& all_views();
// The view named `name`; nullptr when there is none.
const View* find_view(const std::string& name);
// The names, e.g. "a, b or c" (for usage messages and help).
std::string view_names(const std::string& separator = ", ", const std::string& last_separator = " or ");

}  // namespace roverlab::views
