// The preview ray tracer. Per pixel: one primary ray against the spheres;
// the shell (its own scene, so it casts no shadow and no occlusion) is
// composited in front of the sphere hit, layer by layer; a sphere hit is lit
// by a key light (with a shadow ray), a fill light, and an ambient term
// weighted by ambient occlusion from a few short rays. Shading is in linear
// light, written out as sRGB. Rows run in parallel (TBB).
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include "pfill/error.hpp"
#include "pfill/render.hpp"
#include "pfill/srgb.hpp"
#include "render/embree_scene.hpp"

namespace pfill {
namespace {

constexpr int kMaxShellLayers = 16;

struct Rgb {
  float r = 0, g = 0, b = 0;
  Rgb operator+(const Rgb& o) const { return {r + o.r, g + o.g, b + o.b}; }
  Rgb operator*(const Rgb& o) const { return {r * o.r, g * o.g, b * o.b}; }
  Rgb operator*(float s) const { return {r * s, g * s, b * s}; }
};

Rgb linear(const Rgb8& c) { return {srgb8_to_linear(c[0]), srgb8_to_linear(c[1]), srgb8_to_linear(c[2])}; }

uint8_t encode_srgb(float v) {
  v = std::clamp(v, 0.0f, 1.0f);
  const double s = v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
  return static_cast<uint8_t>(std::lround(s * 255.0));
}

// Small, fast, reproducible per-pixel random numbers.
struct Random {
  uint32_t state;
  explicit Random(uint32_t seed) : state(seed * 747796405u + 2891336453u) {}
  float next() {
    state = state * 747796405u + 2891336453u;
    uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    word = (word >> 22u) ^ word;
    return static_cast<float>(word >> 8) * (1.0f / 16777216.0f);
  }
};

RTCRayHit make_ray(const Vec3& origin, const Vec3& direction, float tnear, float tfar) {
  RTCRayHit rh;
  rh.ray.org_x = float(origin.x);
  rh.ray.org_y = float(origin.y);
  rh.ray.org_z = float(origin.z);
  rh.ray.dir_x = float(direction.x);
  rh.ray.dir_y = float(direction.y);
  rh.ray.dir_z = float(direction.z);
  rh.ray.tnear = tnear;
  rh.ray.tfar = tfar;
  rh.ray.time = 0;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  return rh;
}

bool occluded(RTCScene scene, const Vec3& origin, const Vec3& direction, float tfar) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = make_ray(origin, direction, 0.0f, tfar).ray;
  rtcOccluded1(scene, &context, &ray);
  return ray.tfar < 0;  // Embree sets tfar to -inf on a hit
}

// Everything a pixel needs, fixed for the whole image.
struct Scene {
  RTCScene spheres = nullptr;
  RTCScene shell = nullptr;        // null without a shell
  const std::vector<std::array<float, 4>>* sphere_data = nullptr;
  std::vector<Rgb> sphere_colours;  // one per kept sphere, or one for all
  int cut_axis = -1;
  double cut_value = 0;
  Vec3 eye, forward, right, up;
  double tan_h = 0, tan_v = 0;
  Vec3 key_direction, fill_direction;  // towards the lights
  Rgb key{0.95f, 0.92f, 0.86f}, fill{0.22f, 0.25f, 0.32f}, ambient{0.34f, 0.35f, 0.38f};
  Rgb shell_colour;
  float shell_opacity = 0;
  int ao_rays = 0;
  double epsilon = 1e-6;  // offsets of secondary rays, relative to the scene size
};

Rgb shade_sphere(const Scene& s, const RTCRayHit& rh, const Vec3& direction, Random& random) {
  const Vec3 hit = s.eye + direction * rh.ray.tfar;
  Vec3 n = normalize(Vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  if (dot(n, direction) > 0) n = -n;
  const float radius = (*s.sphere_data)[rh.hit.primID][3];
  const Vec3 origin = hit + n * (s.epsilon + 1e-4 * radius);
  const Rgb& albedo = s.sphere_colours.size() == 1 ? s.sphere_colours[0] : s.sphere_colours[rh.hit.primID];

  // Ambient occlusion: cosine-weighted rays over the hemisphere, as far as a
  // few radii, so neighbours darken the gaps between them.
  float visible = 1.0f;
  if (s.ao_rays > 0) {
    const Vec3 a = std::abs(n.x) > 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0);
    const Vec3 t = normalize(cross(a, n)), b = cross(n, t);
    int open = 0;
    for (int k = 0; k < s.ao_rays; ++k) {
      const double u1 = (k + random.next()) / s.ao_rays, u2 = random.next();  // stratified
      const double rr = std::sqrt(u1), phi = 2 * kPi * u2;
      const Vec3 d = t * (rr * std::cos(phi)) + b * (rr * std::sin(phi)) + n * std::sqrt(1 - u1);
      if (!occluded(s.spheres, origin, d, 4.0f * radius)) ++open;
    }
    visible = static_cast<float>(open) / s.ao_rays;
  }
  const double key_cos = dot(n, s.key_direction);
  float key = 0;
  if (key_cos > 0 && !occluded(s.spheres, origin, s.key_direction, std::numeric_limits<float>::infinity()))
    key = static_cast<float>(key_cos);
  const float fill = static_cast<float>(std::max(0.0, dot(n, s.fill_direction)));
  const Vec3 half = normalize(s.key_direction - direction);
  const float specular = key > 0 ? 0.18f * static_cast<float>(std::pow(std::max(0.0, dot(n, half)), 48)) : 0.0f;
  const Rgb diffuse = s.key * key + s.fill * fill + s.ambient * (0.25f + 0.75f * visible);
  return albedo * diffuse + s.key * specular;
}

bool cut_away(const Scene& s, const Vec3& p) { return s.cut_axis >= 0 && p[s.cut_axis] > s.cut_value; }

// Colour along one primary ray; `background` is this row's linear colour.
Rgb trace(const Scene& s, const Vec3& direction, const Rgb& background, Random& random) {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit sphere_hit = make_ray(s.eye, direction, 0.0f, std::numeric_limits<float>::infinity());
  rtcIntersect1(s.spheres, &context, &sphere_hit);
  const bool hit_sphere = sphere_hit.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  const float t_sphere = hit_sphere ? sphere_hit.ray.tfar : std::numeric_limits<float>::infinity();

  // Shell layers in front of the sphere, front to back.
  Rgb colour;
  float transmitted = 1.0f;
  if (s.shell) {
    float tnear = 0.0f;
    for (int layer = 0; layer < kMaxShellLayers; ++layer) {
      RTCRayHit shell_hit = make_ray(s.eye, direction, tnear, t_sphere);
      rtcIntersect1(s.shell, &context, &shell_hit);
      if (shell_hit.hit.geomID == RTC_INVALID_GEOMETRY_ID) break;
      const float t = shell_hit.ray.tfar;
      tnear = t + static_cast<float>(s.epsilon) + t * 1e-6f;
      if (cut_away(s, s.eye + direction * t)) continue;
      const Vec3 n = normalize(Vec3(shell_hit.hit.Ng_x, shell_hit.hit.Ng_y, shell_hit.hit.Ng_z));
      const float facing = static_cast<float>(std::abs(dot(n, direction)));
      // More opaque towards the silhouette, like a thin glass skin.
      const float alpha = std::min(0.6f, s.shell_opacity * (1.0f + 3.0f * std::pow(1.0f - facing, 3.0f)));
      const float light = 0.55f + 0.45f * static_cast<float>(std::abs(dot(n, s.key_direction)));
      colour = colour + s.shell_colour * (light * alpha * transmitted);
      transmitted *= 1.0f - alpha;
    }
  }
  const Rgb behind = hit_sphere ? shade_sphere(s, sphere_hit, direction, random) : background;
  return colour + behind * transmitted;
}

}  // namespace

Rgb8 background_at(const RenderOptions& options, int y, int height) {
  const double t = height > 1 ? static_cast<double>(y) / (height - 1) : 0.0;
  Rgb8 c;
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<uint8_t>(std::lround(options.background_top[k] * (1 - t) + options.background_bottom[k] * t));
  return c;
}

Image render(const ParticleSet& particles, const Mesh* shell, const RenderOptions& options) {
  if (options.width < 1 || options.height < 1 || options.width > 16384 || options.height > 16384)
    throw Error("render: image size " + std::to_string(options.width) + "x" + std::to_string(options.height) +
                " is outside 1..16384 (use e.g. --size 1024x768)");
  if (options.samples_per_axis < 1 || options.samples_per_axis > 8)
    throw Error("render: samples per axis must be 1..8, not " + std::to_string(options.samples_per_axis));
  if (options.ambient_occlusion_rays < 0 || options.ambient_occlusion_rays > 64)
    throw Error("render: ambient occlusion rays must be 0..64");
  validate(particles, "render input");
  if (options.cut && (options.cut->axis < 0 || options.cut->axis > 2))
    throw Error("render: cut axis must be 0 (x), 1 (y) or 2 (z)");

  const Box3 bounds = scene_bounds(particles, shell);
  Scene s;
  Box3 framed = bounds;  // what the automatic camera shows: the part the cut keeps
  if (options.cut) {
    s.cut_axis = options.cut->axis;
    s.cut_value = options.cut->value ? *options.cut->value
                                     : (bounds.empty() ? 0.0 : bounds.centre()[options.cut->axis]);
    if (!framed.empty() && framed.lo[s.cut_axis] < s.cut_value)
      framed.hi[s.cut_axis] = std::min(framed.hi[s.cut_axis], s.cut_value);
  }
  const double aspect = static_cast<double>(options.width) / options.height;
  const Camera camera = options.camera ? *options.camera : frame_camera(framed, options.view, aspect);

  // Spheres that survive the cut, and their colours.
  std::vector<std::array<float, 4>> spheres;
  spheres.reserve(particles.size());
  const bool coloured = particles.has_colours();
  if (!coloured) s.sphere_colours.push_back(linear(options.particle_colour));
  std::array<float, 256> to_linear;
  for (int i = 0; i < 256; ++i) to_linear[i] = srgb8_to_linear(static_cast<uint8_t>(i));
  for (size_t i = 0; i < particles.size(); ++i) {
    const Vec3& p = particles.positions[i];
    if (cut_away(s, p)) continue;
    spheres.push_back({float(p.x), float(p.y), float(p.z), float(particles.radii[i])});
    if (coloured) {
      const Rgb8& c = particles.colours[i];
      s.sphere_colours.push_back({to_linear[c[0]], to_linear[c[1]], to_linear[c[2]]});
    }
  }

  EmbreeDevice device;
  EmbreeScene sphere_scene(device);
  sphere_scene.add_spheres(spheres);
  sphere_scene.commit();
  s.spheres = sphere_scene.get();
  s.sphere_data = &spheres;
  std::unique_ptr<EmbreeScene> shell_scene;
  if (shell && !shell->triangles.empty()) {
    shell_scene = std::make_unique<EmbreeScene>(device);
    shell_scene->add_triangles(*shell);
    shell_scene->commit();
    s.shell = shell_scene->get();
  }

  s.eye = camera.eye;
  s.forward = normalize(camera.target - camera.eye);
  s.right = normalize(cross(s.forward, camera.up));
  s.up = cross(s.right, s.forward);
  s.tan_v = std::tan(camera.vertical_fov_degrees * kPi / 360);
  s.tan_h = s.tan_v * aspect;
  // Lights are fixed to the camera: key from the upper left, fill from the right.
  s.key_direction = normalize(s.right * -0.55 + s.up * 0.75 - s.forward * 0.6);
  s.fill_direction = normalize(s.right * 0.8 + s.up * 0.1 - s.forward * 0.5);
  s.shell_colour = linear(options.shell_colour);
  s.shell_opacity = static_cast<float>(options.shell_opacity);
  s.ao_rays = options.ambient_occlusion_rays;
  s.epsilon = 1e-6 * std::max(bounds.empty() ? 1.0 : bounds.diagonal(), length(camera.eye - camera.target));

  Image image;
  image.width = options.width;
  image.height = options.height;
  image.rgb.resize(static_cast<size_t>(image.width) * image.height * 3);
  const int n = options.samples_per_axis;
  tbb::parallel_for(tbb::blocked_range<int>(0, image.height), [&](const tbb::blocked_range<int>& rows) {
    for (int y = rows.begin(); y != rows.end(); ++y) {
      const Rgb background = linear(background_at(options, y, image.height));
      for (int x = 0; x < image.width; ++x) {
        Random random(static_cast<uint32_t>(y) * 65537u + static_cast<uint32_t>(x) * 2654435761u);
        Rgb sum;
        for (int sy = 0; sy < n; ++sy)
          for (int sx = 0; sx < n; ++sx) {
            const double u = 2.0 * (x + (sx + 0.5) / n) / image.width - 1.0;
            const double v = 1.0 - 2.0 * (y + (sy + 0.5) / n) / image.height;
            const Vec3 direction = normalize(s.forward + s.right * (u * s.tan_h) + s.up * (v * s.tan_v));
            sum = sum + trace(s, direction, background, random);
          }
        const float weight = 1.0f / static_cast<float>(n * n);
        uint8_t* out = &image.rgb[3 * (static_cast<size_t>(y) * image.width + x)];
        out[0] = encode_srgb(sum.r * weight);
        out[1] = encode_srgb(sum.g * weight);
        out[2] = encode_srgb(sum.b * weight);
      }
    }
  });
  return image;
}

}  // namespace pfill
