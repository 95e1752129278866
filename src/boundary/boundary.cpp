// The Embree owner behind pfill::Boundary: scene set-up, ray parity and
// closest-point queries.
#include "pfill/boundary.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <string>

#include "boundary/embree_errors.hpp"
#include "boundary/point_triangle.hpp"
#include "boundary/spread_directions.hpp"
#include "boundary/surface_normals.hpp"
#include "pfill/error.hpp"
#include "pfill/winding_sweep.hpp"

namespace pfill {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A hit whose smallest barycentric coordinate is below this lies, within
// Embree's float rounding, on an edge or a vertex: its ray is re-cast.
constexpr float kEdgeBarycentric = 1e-5f;
constexpr int kRecastAttempts = 12;

template <typename Out, typename F>
std::vector<Out> parallel_map(const std::vector<Vec3>& points, F f) {
  std::vector<Out> out(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) out[i] = f(points[i]);
  });
  return out;
}
struct RayHit {
  float t;
  uint32_t triangle;
  float u, v;
};

// Passed to rtcIntersect1 in place of a plain context; the filter below
// casts back to it. `base` must stay the first member.
struct HitCollector {
  RTCIntersectContext base;
  std::vector<RayHit>* hits;
};

// Records every hit and rejects it, so traversal goes on to the ray's end.
void collect_hit(const RTCFilterFunctionNArguments* args) {
  auto* collector = reinterpret_cast<HitCollector*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] != -1) continue;
    collector->hits->push_back({RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i),
                                RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i)});
    args->valid[i] = 0;
  }
}

}  // namespace

struct Boundary::Impl {
  Mesh mesh;
  BoundaryOptions options;
  SurfaceNormals normals;
  double orientation = 1;  // -1 on inward-oriented meshes
  double extent = 0;       // bounding-box diagonal plus largest |coordinate|
  std::vector<Vec3> directions;
  std::vector<Vec3> perturbations;
  std::unique_ptr<EmbreeErrorLog> errors = std::make_unique<EmbreeErrorLog>();
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;

  // Inside is a non-zero winding number (signed crossings) where every edge
  // is walked once each way; elsewhere (open or inconsistently oriented
  // meshes) ray parity, which does not depend on the winding.
  bool winding_inside = false;
  // Some region is enclosed twice (parts overlap, the surface passes through
  // itself): the pseudonormal then no longer tells the side near the inner
  // surfaces, so signs come from the winding number.
  bool overlapping = false;
  // Overlapping closed parts, each outward: the distance is the union's,
  // the smallest of the parts' signed distances (Parts below).
  bool union_of_parts = false;
  std::vector<uint32_t> triangle_part;  // the connected part of each triangle
  struct Part {
    RTCScene scene = nullptr;
    std::vector<uint32_t> triangles;  // the part's triangles, by the part scene's primitive id
    Box3 box;
  };
  std::vector<Part> parts;

  ~Impl() {
    for (Part& part : parts)
      if (part.scene) rtcReleaseScene(part.scene);
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void throw_if_embree_failed(const char* step) {
    const RTCError code = rtcGetDeviceError(device);
    const std::string first = errors->first_message();
    if (code == RTC_ERROR_NONE && first.empty()) return;
    const std::string message = first.empty() ? embree_error_name(code) : first;
    throw Error(mesh.source + ": Embree failed to " + step + " (" + message +
                "); check the Embree installation and the mesh size");
  }

  void build_scene() {
    device = rtcNewDevice(nullptr);
    if (!device)
      throw Error(std::string("Embree: could not create a device (") + embree_error_name(rtcGetDeviceError(nullptr)) +
                  "); check that libembree3 works on this CPU");
    rtcSetDeviceErrorFunction(device, record_embree_error, errors.get());
    scene = new_scene(nullptr);
    for (Part& part : parts) part.scene = new_scene(&part.triangles);
  }

  // A scene of the given triangles (all: nullptr); its primitive ids index
  // that list.
  RTCScene new_scene(const std::vector<uint32_t>* triangles) {
    RTCScene result = rtcNewScene(device);
    rtcSetSceneFlags(result, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(result, RTC_BUILD_QUALITY_HIGH);
    const size_t count = triangles ? triangles->size() : mesh.triangles.size();

    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      rtcReleaseScene(result);
      throw_if_embree_failed("allocate the geometry buffers");
    }
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.positions[i][k]);
    for (size_t t = 0; t < count; ++t)
      for (int k = 0; k < 3; ++k) indices[3 * t + k] = mesh.triangles[triangles ? (*triangles)[t] : t][k];
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    rtcSetGeometryIntersectFilterFunction(geometry, collect_hit);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(result, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(result);
    throw_if_embree_failed("build the scene");
    return result;
  }

  // Splits the mesh into parts connected through shared vertices, and
  // chooses how inside and distances are decided (see the members).
  void classify() {
    winding_inside = edges_balanced(mesh);
    if (!winding_inside) return;
    overlapping = sweep_winding(mesh, orientation < 0 ? -1 : 1).overlapping();
    if (!overlapping) return;
    std::vector<uint32_t> parent(mesh.positions.size());
    for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto find = [&](uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    for (const Triangle& t : mesh.triangles) {
      parent[find(t[0])] = find(t[1]);
      parent[find(t[1])] = find(t[2]);
    }
    std::vector<int64_t> part_of_root(mesh.positions.size(), -1);
    std::vector<double> volumes;
    triangle_part.resize(mesh.triangles.size());
    const Vec3 centre = mesh.bounds().centre();
    for (uint32_t t = 0; t < mesh.triangles.size(); ++t) {
      const Triangle& tri = mesh.triangles[t];
      int64_t& k = part_of_root[find(tri[0])];
      if (k < 0) {
        k = static_cast<int64_t>(parts.size());
        parts.emplace_back();
        volumes.push_back(0);
      }
      triangle_part[t] = static_cast<uint32_t>(k);
      parts[k].triangles.push_back(t);
      const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
      for (const Vec3* v : {&a, &b, &c}) parts[k].box.add(*v);
      volumes[k] += dot(a - centre, cross(b - centre, c - centre)) / 6.0;
    }
    // The union of parts needs each part to be a solid of its own (no
    // cavity walls, which have negative volume) and a bounded number of
    // parts to ask; otherwise signs still come from the winding number.
    constexpr size_t kMaxParts = 256;
    union_of_parts = parts.size() >= 2 && parts.size() <= kMaxParts &&
                     std::all_of(volumes.begin(), volumes.end(), [&](double v) { return v * orientation > 0; });
    if (!union_of_parts) parts.clear();
  }

  // All hits along one ray, one per triangle; `*near_edge` if any lies on an
  // edge or vertex within rounding.
  void cast(const Vec3& origin, const Vec3& direction, std::vector<RayHit>& hits, bool* near_edge) const {
    hits.clear();
    HitCollector collector;
    rtcInitIntersectContext(&collector.base);
    collector.hits = &hits;
    RTCRayHit rh{};
    rh.ray.org_x = static_cast<float>(origin.x);
    rh.ray.org_y = static_cast<float>(origin.y);
    rh.ray.org_z = static_cast<float>(origin.z);
    rh.ray.dir_x = static_cast<float>(direction.x);
    rh.ray.dir_y = static_cast<float>(direction.y);
    rh.ray.dir_z = static_cast<float>(direction.z);
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = std::numeric_limits<float>::infinity();
    rh.ray.mask = ~0u;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &collector.base, &rh);

    // A high-quality BVH may split a triangle over several leaves: one hit each.
    std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.triangle < b.triangle; });
    hits.erase(std::unique(hits.begin(), hits.end(),
                           [](const RayHit& a, const RayHit& b) { return a.triangle == b.triangle; }),
               hits.end());
    *near_edge = std::any_of(hits.begin(), hits.end(), [](const RayHit& h) {
      return std::min({h.u, h.v, 1.0f - h.u - h.v}) < kEdgeBarycentric;
    });
  }

  // +1 where the ray leaves the solid through triangle t (its outward
  // normal along the ray), -1 where it enters.
  int crossing_sign(uint32_t t, const Vec3& direction) const {
    const Triangle& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    return dot(cross(b - a, c - a), direction) * orientation > 0 ? 1 : -1;
  }

  struct RayCount {
    int crossings = 0;  // surfaces crossed
    int winding = 0;    // signed: the winding number of the origin
  };

  // Crossings of the ray origin + t direction, t > 0, by the triangles of
  // `part` (all: UINT32_MAX).
  RayCount count_crossings(const Vec3& origin, const Vec3& direction, size_t salt, uint32_t part = UINT32_MAX) const {
    std::vector<RayHit> hits;
    const Vec3 d0 = normalize(direction);
    bool near_edge = false;
    auto of_part = [&](const RayHit& h) { return part == UINT32_MAX || triangle_part[h.triangle] == part; };
    Vec3 d = d0;
    for (int attempt = 0; attempt < kRecastAttempts; ++attempt) {
      d = attempt == 0 ? d0 : normalize(d0 + perturbations[(salt * 7 + attempt) % perturbations.size()] * 0.05);
      cast(origin, d, hits, &near_edge);
      if (part != UINT32_MAX) {
        hits.erase(std::remove_if(hits.begin(), hits.end(), [&](const RayHit& h) { return !of_part(h); }), hits.end());
        near_edge = std::any_of(hits.begin(), hits.end(), [](const RayHit& h) {
          return std::min({h.u, h.v, 1.0f - h.u - h.v}) < kEdgeBarycentric;
        });
      }
      if (!near_edge) {
        RayCount c;
        c.crossings = static_cast<int>(hits.size());
        for (const RayHit& h : hits) c.winding += crossing_sign(h.triangle, d);
        return c;
      }
    }
    // Every perturbed ray still grazed an edge (the origin is on or at an
    // edge of the surface): count hits at the same distance once.
    std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    RayCount c;
    float last = -1;
    for (const RayHit& h : hits) {
      if (c.crossings == 0 || h.t - last > 1e-6f * static_cast<float>(extent)) {
        ++c.crossings;
        c.winding += crossing_sign(h.triangle, d);
      }
      last = h.t;
    }
    return c;
  }

  int crossings(const Vec3& origin, const Vec3& direction, size_t salt) const {
    return count_crossings(origin, direction, salt).crossings;
  }

  // Majority vote of the rays: a non-zero winding number on closed meshes,
  // odd parity elsewhere. `part`: inside that part alone.
  bool inside(const Vec3& p, uint32_t part = UINT32_MAX) const {
    const int rays = static_cast<int>(directions.size());
    const int majority = rays / 2 + 1;
    int in = 0, out = 0;
    for (int k = 0; k < rays; ++k) {
      const RayCount c = count_crossings(p, directions[k], k, part);
      if (winding_inside ? c.winding != 0 : c.crossings % 2 != 0) ++in; else ++out;
      if (in >= majority) return true;
      if (out >= majority) return false;
    }
    return in > out;
  }

  struct Search {
    const Impl* impl = nullptr;
    const std::vector<uint32_t>* ids = nullptr;  // primitive id -> triangle, in a part's scene
    Vec3 p;
    float pad = 0;
    double best_d2 = kInf;
    uint32_t triangle = UINT32_MAX;
    PointTriangleResult result;
  };

  static bool visit_triangle(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const uint32_t t = s->ids ? (*s->ids)[args->primID] : args->primID;
    const Triangle& tri = s->impl->mesh.triangles[t];
    const auto& pos = s->impl->mesh.positions;
    const PointTriangleResult r = closest_point_on_triangle(s->p, pos[tri[0]], pos[tri[1]], pos[tri[2]]);
    if (r.distance2 < s->best_d2 || (r.distance2 == s->best_d2 && t < s->triangle)) {
      s->best_d2 = r.distance2;
      s->triangle = t;
      s->result = r;
      // Shrink the search, padded for the float BVH and float query point.
      const float radius = static_cast<float>(std::sqrt(r.distance2)) * (1.0f + 1e-6f) + s->pad;
      if (radius < args->query->radius) {
        args->query->radius = radius;
        return true;
      }
    }
    return false;
  }

  // Closest feature within `radius` (infinity: anywhere); triangle ==
  // UINT32_MAX if none.
  Search search(const Vec3& p, double radius, const Part* part = nullptr) const {
    Search s;
    s.impl = this;
    s.ids = part ? &part->triangles : nullptr;
    s.p = p;
    const double max_abs = std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
    s.pad = static_cast<float>(1e-6 * (extent + max_abs));
    RTCPointQuery query;
    query.x = static_cast<float>(p.x);
    query.y = static_cast<float>(p.y);
    query.z = static_cast<float>(p.z);
    query.time = 0.0f;
    query.radius = std::isfinite(radius) ? static_cast<float>(radius) * (1.0f + 1e-5f) + s.pad
                                         : std::numeric_limits<float>::infinity();
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    rtcPointQuery(part ? part->scene : scene, &query, &context, visit_triangle, &s);
    return s;
  }

  // Signed distance from the closest point `s` found: the pseudonormal's
  // side where it can tell, else the vote of the rays (of `part` alone).
  double signed_from(const Search& s, uint32_t part, bool* used_parity) const {
    const double d = std::sqrt(s.best_d2);
    if (used_parity) *used_parity = false;
    if (d == 0) return 0;
    bool ok = false;
    const Vec3 pseudo = normals.pseudonormal(mesh, s.triangle, s.result.feature, &ok);
    const double side = dot(s.p - s.result.point, pseudo) * orientation;
    if (ok && side != 0 && (!overlapping || part != UINT32_MAX)) return side > 0 ? d : -d;
    if (used_parity) *used_parity = true;
    return inside(s.p, part) ? -d : d;
  }

  // The union of the parts: the smallest of their signed distances (exact
  // outside; inside a lower bound of the depth, exact near the union's
  // surface). `*closest_search` gets the search of the part that gave it.
  double union_signed_distance(const Vec3& p, Search* closest_search) const {
    double best = kInf;
    for (uint32_t k = 0; k < parts.size(); ++k) {
      const Part& part = parts[k];
      const double gap = length(max(max(part.box.lo - p, p - part.box.hi), Vec3{}));
      if (gap > 0 && gap >= best) continue;  // outside its box: this part cannot hold p nor come closer
      const Search s = search(p, kInf, &part);
      if (s.triangle == UINT32_MAX) continue;
      const double v = signed_from(s, k, nullptr);
      if (v < best) {
        best = v;
        if (closest_search) *closest_search = s;
      }
    }
    return best;
  }

  ClosestPoint to_closest_point(const Search& s) const {
    ClosestPoint c;
    c.point = s.result.point;
    c.distance = std::sqrt(s.best_d2);
    c.triangle = s.triangle;
    c.u = s.result.u;
    c.v = s.result.v;
    bool ok = false;
    const Vec3 pseudo = normals.pseudonormal(mesh, s.triangle, s.result.feature, &ok) * orientation;
    if (s.result.feature == TriangleFeature::Face || !(c.distance > 1e-12 * extent)) {
      c.normal = pseudo;
    } else {
      const Vec3 away = (s.p - c.point) / c.distance;
      c.normal = dot(away, pseudo) >= 0 ? away : -away;
    }
    if (c.normal == Vec3{})  // degenerate triangle: fall back on the direction to p
      c.normal = c.distance > 0 ? (s.p - c.point) / c.distance : Vec3{0, 0, 1};
    return c;
  }

  Search search_anywhere(const Vec3& p, double upper_bound) const {
    if (std::isfinite(upper_bound)) {
      Search s = search(p, upper_bound);
      if (s.triangle != UINT32_MAX) return s;
    }
    return search(p, kInf);
  }
};

Boundary::Boundary(const Mesh& mesh, BoundaryOptions options) : impl_(std::make_unique<Impl>()) {
  validate(mesh);
  if (options.parity_rays < 1 || options.parity_rays > 31 || options.parity_rays % 2 == 0)
    throw Error(mesh.source + ": parity_rays must be an odd number from 1 to 31 (got " +
                std::to_string(options.parity_rays) + ")");
  Impl& im = *impl_;
  im.mesh = mesh;
  im.options = options;
  im.normals = compute_surface_normals(mesh);
  im.orientation = im.normals.signed_volume < 0 ? -1.0 : 1.0;
  const Box3 box = mesh.bounds();
  im.extent = box.diagonal() + std::max({std::fabs(box.lo.x), std::fabs(box.lo.y), std::fabs(box.lo.z),
                                         std::fabs(box.hi.x), std::fabs(box.hi.y), std::fabs(box.hi.z)});
  im.directions = spread_directions(options.parity_rays, 0.5);
  im.perturbations = spread_directions(61, 0.25);
  im.classify();
  im.build_scene();
}

Boundary::~Boundary() = default;
Boundary::Boundary(Boundary&&) noexcept = default;
Boundary& Boundary::operator=(Boundary&&) noexcept = default;

bool Boundary::inside(const Vec3& p) const { return impl_->inside(p); }

ClosestPoint Boundary::closest(const Vec3& p) const {
  if (impl_->union_of_parts) {
    Impl::Search s;
    impl_->union_signed_distance(p, &s);
    return impl_->to_closest_point(s);
  }
  return impl_->to_closest_point(impl_->search(p, kInf));
}

std::optional<ClosestPoint> Boundary::closest_within(const Vec3& p, double radius) const {
  if (impl_->union_of_parts) {
    const ClosestPoint c = closest(p);
    if (!(c.distance <= radius)) return std::nullopt;
    return c;
  }
  const Impl::Search s = impl_->search(p, radius);
  if (s.triangle == UINT32_MAX || std::sqrt(s.best_d2) > radius) return std::nullopt;
  return impl_->to_closest_point(s);
}

double Boundary::signed_distance(const Vec3& p) const {
  if (impl_->union_of_parts) return impl_->union_signed_distance(p, nullptr);
  const double d = std::sqrt(impl_->search(p, kInf).best_d2);
  return impl_->inside(p) ? -d : d;
}

double Boundary::fast_signed_distance(const Vec3& p, double upper_bound, bool* used_parity) const {
  if (impl_->union_of_parts) {
    if (used_parity) *used_parity = false;
    return impl_->union_signed_distance(p, nullptr);
  }
  return impl_->signed_from(impl_->search_anywhere(p, upper_bound), UINT32_MAX, used_parity);
}

std::vector<uint8_t> Boundary::inside(const std::vector<Vec3>& points) const {
  return parallel_map<uint8_t>(points, [this](const Vec3& p) { return static_cast<uint8_t>(inside(p)); });
}

std::vector<ClosestPoint> Boundary::closest(const std::vector<Vec3>& points) const {
  return parallel_map<ClosestPoint>(points, [this](const Vec3& p) { return closest(p); });
}

std::vector<double> Boundary::signed_distance(const std::vector<Vec3>& points) const {
  return parallel_map<double>(points, [this](const Vec3& p) { return signed_distance(p); });
}

int Boundary::crossings(const Vec3& origin, const Vec3& direction) const {
  if (!(length(direction) > 0) || !is_finite(direction) || !is_finite(origin))
    throw Error("Boundary::crossings: the ray needs a finite origin and a non-zero finite direction");
  return impl_->crossings(origin, direction, 0);
}

const std::vector<Vec3>& Boundary::parity_directions() const { return impl_->directions; }
const Mesh& Boundary::mesh() const { return impl_->mesh; }
bool Boundary::inward_oriented() const { return impl_->normals.signed_volume < 0; }
double Boundary::signed_volume() const { return impl_->normals.signed_volume; }
bool Boundary::closed() const { return impl_->normals.closed; }
bool Boundary::overlapping() const { return impl_->overlapping; }
bool Boundary::union_of_parts() const { return impl_->union_of_parts; }

}  // namespace pfill
