#include "core/terramechanics/rft.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <memory>
#include <mutex>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

namespace roverlab::terramechanics {

namespace {

// Li, Zhang, Goldman 2013 (Science 339:1408, supplementary Table S2), the
// generic Fourier coefficients, N/cm^3 per unit zeta (alpha_z(0, pi/2) = 1).
constexpr double kA00 = 0.206, kA10 = 0.169, kB11 = 0.212, kB01 = 0.358, kBm11 = 0.055;
constexpr double kC11 = -0.124, kC01 = 0.253, kCm11 = 0.007, kD10 = 0.088;

// alpha from cos/sin of 2 beta and of gamma (no trigonometric calls).
Alpha alpha_of(double cos2b, double sin2b, double cosg, double sing) {
  const double sin_p = sin2b * cosg + cos2b * sing;  // sin(2 beta + gamma)
  const double cos_p = cos2b * cosg - sin2b * sing;  // cos(2 beta + gamma)
  const double sin_m = cos2b * sing - sin2b * cosg;  // sin(-2 beta + gamma)
  const double cos_m = cos2b * cosg + sin2b * sing;  // cos(-2 beta + gamma)
  // Li 2013 Eq. S2: alpha_z = sum A cos + B sin, alpha_x = sum C cos + D sin over (m, n) in {-1, 0, 1} x {0, 1}.
  return {kC11 * cos_p + kC01 * cosg + kCm11 * cos_m + kD10 * sin2b,
          kA00 + kA10 * cos2b + kB11 * sin_p + kB01 * sing + kBm11 * sin_m};
}

void add_rim(std::vector<RftElement>& out, const Wheel& w, const RftResolution& res) {
  const double r = w.radius, b = w.width, dth = M_PI / res.angles, dy = b / res.across;
  for (int i = 0; i < res.angles; ++i) {
    const double th = -M_PI / 2.0 + (i + 0.5) * dth;  // from the bottom, positive forward
    const double s = std::sin(th), c = std::cos(th);
    for (int k = 0; k < res.across; ++k) {
      const double y = -b / 2.0 + (k + 0.5) * dy;
      out.push_back({r * s, y, -r * c, s, 0.0, -c, r * dth * dy, RftPart::rim});
    }
  }
}

void add_sides(std::vector<RftElement>& out, const Wheel& w, const RftResolution& res) {
  const double r = w.radius, dth = M_PI / res.angles, dr = r / res.rings;
  for (int side = -1; side <= 1; side += 2) {
    for (int i = 0; i < res.angles; ++i) {
      const double th = -M_PI / 2.0 + (i + 0.5) * dth;
      const double s = std::sin(th), c = std::cos(th);
      for (int k = 0; k < res.rings; ++k) {
        const double rho = (k + 0.5) * dr;
        out.push_back({rho * s, side * w.width / 2.0, -rho * c, 0.0, double(side), 0.0, rho * dr * dth, RftPart::side});
      }
    }
  }
}

// One grouser at angle th: front and back faces (normals along and against
// the direction of growing th) at th +- half its thickness, and its tip.
void add_grouser(std::vector<RftElement>& out, const Wheel& w, double height, double th, double weight,
                 const RftResolution& res) {
  const double r = w.radius, b = w.width, t = w.grouser_thickness;
  const double dy = b / res.across, dh = height / res.grouser_rows;
  const double half = t / (2.0 * r);
  for (int face = -1; face <= 1; face += 2) {
    const double a = th + face * half;
    const double s = std::sin(a), c = std::cos(a);
    for (int j = 0; j < res.grouser_rows; ++j) {
      const double rho = r + (j + 0.5) * dh;
      for (int k = 0; k < res.across; ++k) {
        const double y = -b / 2.0 + (k + 0.5) * dy;
        out.push_back({rho * s, y, -rho * c, face * c, 0.0, face * s, weight * dh * dy, RftPart::grouser});
      }
    }
  }
  if (!(t > 0.0)) return;
  const double s = std::sin(th), c = std::cos(th), tip = r + height;
  for (int k = 0; k < res.across; ++k) {
    const double y = -b / 2.0 + (k + 0.5) * dy;
    out.push_back({tip * s, y, -tip * c, s, 0.0, -c, weight * t * dy, RftPart::grouser});
  }
}

void add_grousers(std::vector<RftElement>& out, const Wheel& w, double height, const RftResolution& res) {
  if (w.grouser_count <= 0 || !(height > 0.0)) return;
  const double pitch = 2.0 * M_PI / w.grouser_count;
  const int phases = std::max(1, res.grouser_phases);
  for (int g = 0; g < w.grouser_count; ++g) {
    for (int p = 0; p < phases; ++p) {
      // Angle from the bottom wrapped into (-pi, pi]; the lower half only.
      double th = std::remainder(g * pitch + (p + 0.5) * pitch / phases, 2.0 * M_PI);
      if (std::abs(th) > M_PI / 2.0) continue;
      add_grouser(out, w, height, th, 1.0 / phases, res);
    }
  }
}

}  // namespace

Alpha generic_alpha(double beta, double gamma) {
  return alpha_of(std::cos(2.0 * beta), std::sin(2.0 * beta), std::cos(gamma), std::sin(gamma));
}

std::vector<RftElement> rft_wheel_mesh(const Wheel& wheel, double grouser_height_scale, const RftResolution& res) {
  std::vector<RftElement> out;
  out.reserve(static_cast<std::size_t>(res.angles * (res.across + 2 * res.rings)) +
              static_cast<std::size_t>(std::max(0, wheel.grouser_count) * res.grouser_phases *
                                       (2 * res.grouser_rows + 1) * res.across));
  add_rim(out, wheel, res);
  add_sides(out, wheel, res);
  add_grousers(out, wheel, grouser_height_scale * wheel.grouser_height, res);
  return out;
}

Vec3 rft_element_stress(const RftElement& e, const Vec3& u) {
  const double speed = std::sqrt(u.x * u.x + u.y * u.y + u.z * u.z);
  // Leading elements only (Li 2013): outward normal along the velocity.
  if (!(speed > 0.0) || !(e.nx * u.x + e.ny * u.y + e.nz * u.z > 0.0)) return {0.0, 0.0, 0.0};
  // The vertical plane of the velocity (Treers et al. 2021): r along its
  // horizontal part (else the normal's), theta = z x r across it.
  double hx = u.x, hy = u.y;
  double h = std::sqrt(hx * hx + hy * hy);
  if (h <= 1e-9 * speed) {
    hx = e.nx;
    hy = e.ny;
    h = std::sqrt(hx * hx + hy * hy);
    if (h <= 1e-12) {
      hx = 1.0;
      hy = 0.0;
      h = 1.0;
    }
  }
  const double rx = hx / h, ry = hy / h;
  const double cosg = (u.x * rx + u.y * ry) / speed, sing = -u.z / speed;  // gamma below the horizontal
  const double n_r = e.nx * rx + e.ny * ry, n_t = -e.nx * ry + e.ny * rx, n_z = e.nz;
  const double l2 = n_r * n_r + n_z * n_z;
  if (l2 <= 1e-24) return {0.0, 0.0, 0.0};
  // The element's angle in that plane, tan(beta) = -n_r / n_z (Li 2013 Fig. 1).
  const double cos2b = (n_z * n_z - n_r * n_r) / l2, sin2b = -2.0 * n_r * n_z / l2;
  const Alpha a = alpha_of(cos2b, sin2b, cosg, sing);
  const double l = std::sqrt(l2);
  // In the plane, the stress on the element's projection l dA; across it,
  // the normal pressure p = -(a . n') on the same projection along -n_theta.
  const double f_r = -a.x * l, f_z = a.z * l;
  const double pressure = (a.x * n_r - a.z * n_z) / l;  // per unit projected area
  const double f_t = -pressure * l * n_t;
  return {e.area * (f_r * rx - f_t * ry), e.area * (f_r * ry + f_t * rx), e.area * f_z};
}

WheelMotion rft_wheel_motion(double slip, double slip_angle, SlipDefinition definition) {
  // 90 deg as the limit from below (cos beta >= 1e-6): there the rim moves in
  // its own plane, and the front half leads as at any smaller angle.
  const double c = std::max(std::cos(slip_angle), 1e-6), s = std::sin(slip_angle);
  if (definition == SlipDefinition::travel) return {{(1.0 - slip) * c, (1.0 - slip) * s, 0.0}, 1.0};
  // Longitudinal: v_x = (1 - s) r w, v_y = v_x tan(beta); scaled by cos(beta).
  const double vx = 1.0 - slip;
  return {{vx * c, vx * s, 0.0}, c};
}

namespace {

// The meshes of the last wheels evaluated (geometry and grouser height
// scale; a study's file may hold several wheels), shared by every thread,
// each with a generation that names it in the motion caches below.
struct MeshCache {
  double radius = -1, width = -1, height = -1, thickness = -1;
  int count = -1;
  unsigned long generation = 0;
  std::vector<RftElement> mesh;
};
// Two fits side by side, each at a grouser height's x and x +- h, and the
// wheels of the file besides.
constexpr std::size_t kCachedMeshes = 16;

// The mesh with the elements that differ only across the wheel (in y)
// merged, their areas summed: the rigid-body velocity v_c + omega y x p has
// no term in p_y, and no output depends on it (the torque is about y), so
// such elements carry the same stress per area and immersion threshold. The
// rim's and the grousers' rows across the width become one element each
// (3,000 -> 1,300 elements for a wheel of 15 grousers); the sums are the same
// up to rounding.
std::vector<RftElement> merged_across(const std::vector<RftElement>& mesh) {
  std::vector<RftElement> out;
  out.reserve(mesh.size());
  for (const RftElement& e : mesh) {
    if (!out.empty()) {
      RftElement& last = out.back();
      if (last.px == e.px && last.pz == e.pz && last.nx == e.nx && last.ny == e.ny && last.nz == e.nz &&
          last.part == e.part) {
        last.area += e.area;
        continue;
      }
    }
    out.push_back(e);
  }
  return out;
}

// The mesh of wheel w at this grouser height scale, shared by every thread
// (a mutex around the list; a mesh is immutable and held by whoever uses it,
// so that dropping it from the list never frees a mesh in use). Built outside
// the lock; of two threads that built the same mesh, the first one's is kept.
std::shared_ptr<const MeshCache> cached_mesh(const Wheel& w, double grouser_height_scale) {
  struct Entry {
    std::shared_ptr<const MeshCache> mesh;
    unsigned long used;  // when it was last asked for (the cache's clock)
  };
  static std::mutex mutex;
  static std::vector<Entry> cache;
  static unsigned long clock = 0;
  static std::atomic<unsigned long> generations{0};
  const double height = grouser_height_scale * w.grouser_height;
  const auto find = [&]() -> std::shared_ptr<const MeshCache> {
    for (Entry& e : cache) {
      const MeshCache& c = *e.mesh;
      if (c.radius == w.radius && c.width == w.width && c.height == height && c.thickness == w.grouser_thickness &&
          c.count == w.grouser_count) {
        e.used = ++clock;
        return e.mesh;
      }
    }
    return nullptr;
  };
  {
    const std::lock_guard<std::mutex> lock(mutex);
    if (auto found = find()) return found;
  }
  auto built = std::make_shared<const MeshCache>(MeshCache{w.radius, w.width, height, w.grouser_thickness,
                                                           w.grouser_count, ++generations,
                                                           merged_across(rft_wheel_mesh(w, grouser_height_scale))});
  const std::lock_guard<std::mutex> lock(mutex);
  if (auto found = find()) return found;
  // Full: the mesh asked for least recently makes room. Starting the list
  // over instead dropped the meshes a fit beside this one was using (its
  // grouser heights at x and x +- h), and every list of theirs was built
  // again under a new generation: 30 % more meshes on two threads.
  if (cache.size() >= kCachedMeshes) {
    cache.erase(
        std::min_element(cache.begin(), cache.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; }));
  }
  cache.push_back({built, ++clock});
  return built;
}

// An element that carries stress at this motion: its force per unit depth
// and unit material scale, its height above the rim's bottom z, and how
// squarely it pushes along its horizontal motion (0..1).
struct Stressed {
  const RftElement* element;
  Vec3 force;
  double z, pushes;
};

// ... and with a pile-up: the factor m = 1 + pile-up x pushes, its depth at
// sinkage s being m s - z (the surface ahead of a face that pushes sand
// raised by a fraction of the sinkage), so it is immersed above s = z / m.
struct Loaded {
  const RftElement* element;
  Vec3 force;
  double z, pushes, m, threshold;
};

// The order of a sorted list: by threshold, ties by the element's place in
// its mesh. A total order, so any sort (and any history of the list) gives
// the same sequence, and the sums over it the same bits.
bool before(const Loaded& a, const Loaded& b) {
  return a.threshold < b.threshold || (a.threshold == b.threshold && a.element < b.element);
}

void pile(Loaded& l, double pileup) {
  l.m = 1.0 + pileup * l.pushes;
  l.threshold = l.z / l.m;
}

std::vector<Stressed> stressed_elements(const std::vector<RftElement>& mesh, const Wheel& w,
                                        const WheelMotion& motion) {
  std::vector<Stressed> out;
  out.reserve(mesh.size());
  const double omega = motion.rim_speed / w.radius;
  for (const RftElement& e : mesh) {
    // Rigid-body velocity of the element: v_c + omega y x p.
    const Vec3 u{motion.centre.x + omega * e.pz, motion.centre.y, motion.centre.z - omega * e.px};
    const Vec3 f = rft_element_stress(e, u);
    if (f.x == 0.0 && f.y == 0.0 && f.z == 0.0) continue;
    const double h = std::sqrt(u.x * u.x + u.y * u.y);
    const double pushes = h > 0.0 ? std::max(0.0, (e.nx * u.x + e.ny * u.y) / h) : 0.0;
    out.push_back({&e, f, e.pz + w.radius, pushes});
  }
  return out;
}

// Sorted by immersion threshold.
std::vector<Loaded> loaded_elements(const std::vector<Stressed>& stressed, double pileup) {
  std::vector<Loaded> out;
  out.reserve(stressed.size());
  for (const Stressed& e : stressed) {
    out.push_back({e.element, e.force, e.z, e.pushes, 0.0, 0.0});
    pile(out.back(), pileup);
  }
  std::sort(out.begin(), out.end(), before);
  return out;
}

// A sorted list again at another pile-up. A fit changes the pile-up by
// little from one evaluation to the next, so the list is nearly in order:
// insertion sort, in time linear in the list and the elements it moves,
// unless they are many (then a full sort). The same order either way.
void repile(std::vector<Loaded>& list, double pileup) {
  for (Loaded& l : list) pile(l, pileup);
  std::size_t moves = 0;
  const std::size_t budget = 8 * list.size();
  for (std::size_t i = 1; i < list.size(); ++i) {
    const Loaded l = list[i];
    std::size_t j = i;
    for (; j > 0 && before(l, list[j - 1]) && moves <= budget; --j, ++moves) list[j] = list[j - 1];
    list[j] = l;
    if (moves > budget) {
      std::sort(list.begin(), list.end(), before);
      return;
    }
  }
}

// The stresses depend on the mesh and the motion, not on the load, the
// material scale, the depth scale or the pile-up: a fit evaluates the same
// rows again and again with other values of those. So the stressed elements
// of the motions met and their sorted list without a pile-up are kept for
// every thread (SharedLists), and each thread keeps its sorted lists at the
// last pile-up it asked for (a pile-up re-sorts its list in place). Past
// kCachedElements the shared lists drop those of the meshes used least
// recently and a thread's lists start over; an entry of a mesh no longer
// cached is never matched again, as its generation is gone. Results are those of a
// fresh computation, bit for bit (the sort's order is total), whichever
// thread computed them.
struct MotionKey {
  unsigned long generation;
  double cx, cy, cz, rim, radius;
  bool operator==(const MotionKey& o) const {
    return generation == o.generation && cx == o.cx && cy == o.cy && cz == o.cz && rim == o.rim && radius == o.radius;
  }
};
struct MotionKeyHash {
  std::size_t operator()(const MotionKey& k) const {
    std::size_t h = std::hash<unsigned long>()(k.generation);
    for (const double v : {k.cx, k.cy, k.cz, k.rim, k.radius}) {
      h ^= std::hash<double>()(v) + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
    }
    return h;
  }
};
constexpr std::size_t kCachedElements = std::size_t{1} << 21;  // about 120 MB at most, and as much per thread

// The lists every thread shares: a mutex around the maps, each list
// immutable and held by whoever uses it (dropping it frees none in use).
// Computed outside the lock; of two threads that computed the same list, the
// first one's is kept.
class SharedLists {
 public:
  std::shared_ptr<const std::vector<Stressed>> stressed(const MotionKey& key, const MeshCache& mesh, const Wheel& w,
                                                        const WheelMotion& motion) {
    if (auto found = find(stressed_, key)) return found;
    return keep(stressed_, key, std::make_shared<const std::vector<Stressed>>(stressed_elements(mesh.mesh, w, motion)));
  }
  std::shared_ptr<const std::vector<Loaded>> sorted(const MotionKey& key, const MeshCache& mesh, const Wheel& w,
                                                    const WheelMotion& motion) {
    if (auto found = find(sorted_, key)) return found;
    return keep(sorted_, key,
                std::make_shared<const std::vector<Loaded>>(loaded_elements(*stressed(key, mesh, w, motion), 0.0)));
  }

 private:
  template <class T>
  using Map = std::unordered_map<MotionKey, std::shared_ptr<const std::vector<T>>, MotionKeyHash>;
  template <class T>
  std::shared_ptr<const std::vector<T>> find(const Map<T>& map, const MotionKey& key) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto found = map.find(key);
    if (found == map.end()) return nullptr;
    used_[key.generation] = ++clock_;
    return found->second;
  }
  template <class T>
  std::shared_ptr<const std::vector<T>> keep(Map<T>& map, const MotionKey& key,
                                             std::shared_ptr<const std::vector<T>> list) {
    const std::lock_guard<std::mutex> lock(mutex_);
    const auto found = map.find(key);
    if (found != map.end()) return found->second;
    if (elements_ + list->size() > kCachedElements) make_room();
    used_[key.generation] = ++clock_;
    elements_ += list->size();
    return map.emplace(key, std::move(list)).first->second;
  }
  // Full: the lists of the meshes asked for least recently are dropped
  // until half the room is free. Starting over instead dropped, with the
  // dead meshes of a fit that moves a grouser height, the lists a fit beside
  // it (at one mesh) asks for at every evaluation, and built them again.
  void make_room() {
    std::unordered_map<unsigned long, std::size_t> held;  // elements per mesh
    for (const auto& [key, list] : stressed_) held[key.generation] += list->size();
    for (const auto& [key, list] : sorted_) held[key.generation] += list->size();
    std::vector<std::pair<unsigned long, unsigned long>> by_use;  // (last use, generation)
    by_use.reserve(held.size());
    for (const auto& [generation, elements] : held) by_use.emplace_back(used_[generation], generation);
    std::sort(by_use.begin(), by_use.end());
    std::unordered_set<unsigned long> dropped;
    for (const auto& [use, generation] : by_use) {
      if (elements_ <= kCachedElements / 2) break;
      dropped.insert(generation);
      elements_ -= held[generation];
      used_.erase(generation);
    }
    const auto drop = [&](auto& map) {
      for (auto it = map.begin(); it != map.end();) it = dropped.count(it->first.generation) ? map.erase(it) : ++it;
    };
    drop(stressed_);
    drop(sorted_);
  }
  std::mutex mutex_;
  Map<Stressed> stressed_;
  Map<Loaded> sorted_;  // without a pile-up
  std::size_t elements_ = 0;
  std::unordered_map<unsigned long, unsigned long> used_;  // a mesh's (generation's) last use, on clock_
  unsigned long clock_ = 0;
};

// A motion's sorted list at the pile-up it was last asked for (this thread's).
struct Piled {
  double pileup;
  std::vector<Loaded> list;
};
struct PiledCache {
  std::unordered_map<MotionKey, Piled, MotionKeyHash> piled;
  std::size_t elements = 0;
};

// The sorted list of a motion at a pile-up: `list`, which `shared` (when
// set) keeps alive; a list at a pile-up is this thread's and stays valid
// until its next call.
struct LoadedList {
  std::shared_ptr<const std::vector<Loaded>> shared;
  const std::vector<Loaded>* list = nullptr;
};

LoadedList cached_loaded(const MeshCache& mesh, const Wheel& w, const WheelMotion& motion, double pileup) {
  static SharedLists shared;
  thread_local PiledCache cache;
  const MotionKey key{mesh.generation, motion.centre.x, motion.centre.y, motion.centre.z, motion.rim_speed, w.radius};
  if (pileup == 0.0) {
    LoadedList out;
    out.shared = shared.sorted(key, mesh, w, motion);
    out.list = out.shared.get();
    return out;
  }
  const auto found = cache.piled.find(key);
  if (found != cache.piled.end()) {
    if (found->second.pileup != pileup) repile(found->second.list, pileup);
    found->second.pileup = pileup;
    return {nullptr, &found->second.list};
  }
  std::vector<Loaded> list = loaded_elements(*shared.stressed(key, mesh, w, motion), pileup);
  if (cache.elements + list.size() > kCachedElements) {
    cache.piled.clear();
    cache.elements = 0;
  }
  cache.elements += list.size();
  return {nullptr, &cache.piled.emplace(key, Piled{pileup, std::move(list)}).first->second.list};
}

// Sinkage s from F_z(s) = W. With the depth-dependent scale zeta (1 + k d /
// r), F_z is a quadratic in s between consecutive immersion thresholds
// (prefix sums); the first interval where it reaches W brackets the root,
// found there by bisection. NaN when F_z stays below W up to s = r.
double solve_sinkage(const std::vector<Loaded>& loaded, double zeta, double load, double radius, double depth_scale) {
  const double kq = depth_scale / radius;
  double c2 = 0.0, c1 = 0.0, c0 = 0.0;
  for (std::size_t j = 0; j < loaded.size(); ++j) {
    const Loaded& l = loaded[j];
    if (l.threshold >= radius) break;
    const double fz = zeta * l.force.z;
    c2 += kq * fz * l.m * l.m;
    c1 += fz * l.m - 2.0 * kq * fz * l.m * l.z;
    c0 += -fz * l.z + kq * fz * l.z * l.z;
    const double lo = l.threshold;
    const double hi = j + 1 < loaded.size() ? std::min(loaded[j + 1].threshold, radius) : radius;
    auto fz_at = [&](double s) { return (c2 * s + c1) * s + c0; };
    if (!(hi > lo) || fz_at(hi) < load) continue;
    double a = lo, b = hi;
    for (int it = 0; it < 100 && b - a > 1e-14 * radius; ++it) {
      const double mid = 0.5 * (a + b);
      (fz_at(mid) < load ? a : b) = mid;
    }
    return 0.5 * (a + b);
  }
  return NAN;
}

}  // namespace

SlipAngleTraction evaluate_rft(const Soil& soil, const Wheel& wheel, double load, double slip, double slip_angle,
                               const ModelOptions& options) {
  SlipAngleTraction t;
  t.slip_angle = slip_angle;
  const Extensions& e = options.extensions;
  const double zeta = soil.rft_scale * e.soil_strength;
  if (!std::isfinite(load) || load <= 0.0 || !std::isfinite(slip) || std::abs(slip) > 1.0 ||
      !std::isfinite(slip_angle) || std::abs(slip_angle) > M_PI / 2.0 || !(wheel.radius > 0.0) ||
      !(wheel.width > 0.0) || !(zeta > 0.0) || !std::isfinite(zeta) || !(e.rft_pileup >= 0.0) ||
      !(e.rft_depth_scale > -1.0) || !(e.grouser_effectiveness >= 0.0)) {
    t.status = TractionStatus::invalid_input;
    return t;
  }
  const std::shared_ptr<const MeshCache> mesh = cached_mesh(wheel, e.grousers ? e.grouser_effectiveness : 1.0);
  const WheelMotion motion = rft_wheel_motion(slip, slip_angle, options.slip_definition);
  const LoadedList held = cached_loaded(*mesh, wheel, motion, e.rft_pileup);
  const std::vector<Loaded>& loaded = *held.list;
  const double s = solve_sinkage(loaded, zeta, load, wheel.radius, e.rft_depth_scale);
  if (!std::isfinite(s)) {
    t.status = TractionStatus::unsupported_load;
    return t;
  }
  const double kq = e.rft_depth_scale / wheel.radius;
  double resistance = 0.0;  // the resisting elements' share of -F_x
  // Sorted by immersion threshold: past s (with a margin far above rounding),
  // no element is immersed.
  const double last = s + 1e-9 * wheel.radius;
  for (const Loaded& l : loaded) {
    if (l.threshold > last) break;
    const double d = l.m * s - l.z;
    if (!(d > 0.0)) continue;
    const double g = d * (1.0 + kq * d);  // zeta (1 + k d / r) d
    const Vec3 f{zeta * l.force.x * g, zeta * l.force.y * g, zeta * l.force.z * g};
    if (f.x < 0.0) resistance -= f.x;
    t.drawbar_pull += f.x;
    (l.element->part == RftPart::side ? t.sidewall : t.lateral_shear) += f.y;
    t.resistive_torque += l.element->px * f.z - l.element->pz * f.x;  // -(p x F)_y
  }
  t.status = TractionStatus::ok;
  t.sinkage = s;
  t.entry_angle = std::acos(std::clamp(1.0 - s / wheel.radius, -1.0, 1.0));
  t.lateral_force = t.lateral_shear + t.sidewall;
  t.motion_resistance = resistance;
  return t;
}

}  // namespace roverlab::terramechanics
