// The Embree owner behind pfill::Boundary: scene set-up, ray parity and
// closest-point queries.
#include "pfill/boundary.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <mutex>
#include <string>

#include "boundary/point_triangle.hpp"
#include "boundary/surface_normals.hpp"
#include "pfill/error.hpp"

namespace pfill {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
// A hit whose smallest barycentric coordinate is below this lies, within
// Embree's float rounding, on an edge or a vertex: its ray is re-cast.
constexpr float kEdgeBarycentric = 1e-5f;
constexpr int kRecastAttempts = 12;

const char* embree_error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error";
}

// Embree reports errors through a C callback, which must not throw: the
// first message is kept here and thrown after the Embree call returns.
struct EmbreeErrorLog {
  std::mutex mutex;
  std::string first;
};

void record_embree_error(void* user, RTCError code, const char* message) {
  auto* log = static_cast<EmbreeErrorLog*>(user);
  std::lock_guard<std::mutex> lock(log->mutex);
  if (log->first.empty())
    log->first = std::string(embree_error_name(code)) + (message ? std::string(": ") + message : std::string());
}

// Unit vectors spread over the sphere (golden spiral), then turned by a fixed
// irrational rotation so none lies in an axis plane or along a mesh's
// natural symmetry directions.
std::vector<Vec3> spread_directions(int count, double offset) {
  const double golden = 3.14159265358979323846 * (3.0 - std::sqrt(5.0));
  const Vec3 axis = normalize(Vec3(1.0, std::sqrt(2.0), std::sqrt(3.0)));
  const double angle = 1.0, cs = std::cos(angle), sn = std::sin(angle);
  std::vector<Vec3> dirs;
  for (int i = 0; i < count; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / count;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    const double phi = golden * i + offset;
    const Vec3 d(r * std::cos(phi), r * std::sin(phi), z);
    // Rodrigues rotation about `axis`.
    dirs.push_back(normalize(d * cs + cross(axis, d) * sn + axis * (dot(axis, d) * (1 - cs))));
  }
  return dirs;
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

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  void throw_if_embree_failed(const char* step) {
    const RTCError code = rtcGetDeviceError(device);
    std::string message;
    {
      std::lock_guard<std::mutex> lock(errors->mutex);
      message = errors->first;
    }
    if (code == RTC_ERROR_NONE && message.empty()) return;
    if (message.empty()) message = embree_error_name(code);
    throw Error(mesh.source + ": Embree failed to " + step + " (" + message +
                "); check the Embree installation and the mesh size");
  }

  void build_scene() {
    device = rtcNewDevice(nullptr);
    if (!device)
      throw Error(std::string("Embree: could not create a device (") + embree_error_name(rtcGetDeviceError(nullptr)) +
                  "); check that libembree3 works on this CPU");
    rtcSetDeviceErrorFunction(device, record_embree_error, errors.get());
    scene = rtcNewScene(device);
    rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);

    RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), mesh.positions.size()));
    auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
        geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), mesh.triangles.size()));
    if (!vertices || !indices) {
      rtcReleaseGeometry(geometry);
      throw_if_embree_failed("allocate the geometry buffers");
    }
    for (size_t i = 0; i < mesh.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.positions[i][k]);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) indices[3 * t + k] = mesh.triangles[t][k];
    rtcSetGeometryBuildQuality(geometry, RTC_BUILD_QUALITY_HIGH);
    rtcSetGeometryIntersectFilterFunction(geometry, collect_hit);
    rtcCommitGeometry(geometry);
    rtcAttachGeometry(scene, geometry);
    rtcReleaseGeometry(geometry);
    rtcCommitScene(scene);
    throw_if_embree_failed("build the scene");
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

  int crossings(const Vec3& origin, const Vec3& direction, size_t salt) const {
    std::vector<RayHit> hits;
    const Vec3 d0 = normalize(direction);
    bool near_edge = false;
    for (int attempt = 0; attempt < kRecastAttempts; ++attempt) {
      const Vec3 d = attempt == 0
                         ? d0
                         : normalize(d0 + perturbations[(salt * 7 + attempt) % perturbations.size()] * 0.05);
      cast(origin, d, hits, &near_edge);
      if (!near_edge) return static_cast<int>(hits.size());
    }
    // Every perturbed ray still grazed an edge (the origin is on or at an
    // edge of the surface): count hits at the same distance once.
    std::sort(hits.begin(), hits.end(), [](const RayHit& a, const RayHit& b) { return a.t < b.t; });
    int count = 0;
    float last = -1;
    for (const RayHit& h : hits) {
      if (count == 0 || h.t - last > 1e-6f * static_cast<float>(extent)) ++count;
      last = h.t;
    }
    return count;
  }

  bool inside(const Vec3& p) const {
    const int rays = static_cast<int>(directions.size());
    const int majority = rays / 2 + 1;
    int in = 0, out = 0;
    for (int k = 0; k < rays; ++k) {
      if (crossings(p, directions[k], k) % 2) ++in; else ++out;
      if (in >= majority) return true;
      if (out >= majority) return false;
    }
    return in > out;
  }

  struct Search {
    const Impl* impl = nullptr;
    Vec3 p;
    float pad = 0;
    double best_d2 = kInf;
    uint32_t triangle = UINT32_MAX;
    PointTriangleResult result;
  };

  static bool visit_triangle(RTCPointQueryFunctionArguments* args) {
    auto* s = static_cast<Search*>(args->userPtr);
    const uint32_t t = args->primID;
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
  Search search(const Vec3& p, double radius) const {
    Search s;
    s.impl = this;
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
    rtcPointQuery(scene, &query, &context, visit_triangle, &s);
    return s;
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
  for (const Vec3& p : mesh.positions)
    for (int k = 0; k < 3; ++k)
      if (std::fabs(p[k]) > 1e30)
        throw Error(mesh.source + ": a coordinate exceeds 1e30, beyond single precision; rescale the mesh");
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
  im.build_scene();
}

Boundary::~Boundary() = default;
Boundary::Boundary(Boundary&&) noexcept = default;
Boundary& Boundary::operator=(Boundary&&) noexcept = default;

bool Boundary::inside(const Vec3& p) const { return impl_->inside(p); }

ClosestPoint Boundary::closest(const Vec3& p) const { return impl_->to_closest_point(impl_->search(p, kInf)); }

std::optional<ClosestPoint> Boundary::closest_within(const Vec3& p, double radius) const {
  const Impl::Search s = impl_->search(p, radius);
  if (s.triangle == UINT32_MAX || std::sqrt(s.best_d2) > radius) return std::nullopt;
  return impl_->to_closest_point(s);
}

double Boundary::signed_distance(const Vec3& p) const {
  const double d = std::sqrt(impl_->search(p, kInf).best_d2);
  return impl_->inside(p) ? -d : d;
}

double Boundary::fast_signed_distance(const Vec3& p, double upper_bound, bool* used_parity) const {
  const Impl::Search s = impl_->search_anywhere(p, upper_bound);
  const double d = std::sqrt(s.best_d2);
  if (used_parity) *used_parity = false;
  if (d == 0) return 0;
  bool ok = false;
  const Vec3 pseudo = impl_->normals.pseudonormal(impl_->mesh, s.triangle, s.result.feature, &ok);
  const double side = dot(p - s.result.point, pseudo) * impl_->orientation;
  if (ok && side != 0) return side > 0 ? d : -d;
  if (used_parity) *used_parity = true;
  return impl_->inside(p) ? -d : d;
}

namespace {
template <typename Out, typename F>
std::vector<Out> parallel_map(const std::vector<Vec3>& points, F f) {
  std::vector<Out> out(points.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, points.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) out[i] = f(points[i]);
  });
  return out;
}
}  // namespace

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

}  // namespace pfill
