// Views, cuts and the automatic framing of the preview camera.
#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "pfill/error.hpp"
#include "pfill/render.hpp"

namespace pfill {
namespace {


// Direction from the target towards the eye, and the up vector, per view.
void view_direction(View view, Vec3& towards_eye, Vec3& up) {
  up = Vec3(0, 1, 0);
  switch (view) {
    case View::ThreeQuarter: {
      // 35 degrees round from the front, 20 degrees above.
      const double yaw = 35 * kPi / 180, pitch = 20 * kPi / 180;
      towards_eye = Vec3(std::sin(yaw) * std::cos(pitch), std::sin(pitch), std::cos(yaw) * std::cos(pitch));
      return;
    }
    case View::Front: towards_eye = Vec3(0, 0, 1); return;
    case View::Side: towards_eye = Vec3(1, 0, 0); return;
    case View::Top: towards_eye = Vec3(0, 1, 0); up = Vec3(0, 0, -1); return;
    case View::Iso: towards_eye = normalize(Vec3(1, 1, 1)); return;
  }
}

}  // namespace

View parse_view(const std::string& name) {
  if (name == "three-quarter" || name == "default") return View::ThreeQuarter;
  if (name == "front") return View::Front;
  if (name == "side") return View::Side;
  if (name == "top") return View::Top;
  if (name == "iso") return View::Iso;
  throw Error("unknown view '" + name + "' (use front, side, top, iso or three-quarter)");
}

Cut parse_cut(const std::string& text) {
  Cut cut;
  const std::string axis = text.substr(0, text.find('='));
  if (axis == "x") cut.axis = 0;
  else if (axis == "y") cut.axis = 1;
  else if (axis == "z") cut.axis = 2;
  else throw Error("bad cut '" + text + "': use x, y or z, optionally with =VALUE (e.g. --cut z=0.1)");
  if (text.size() > axis.size()) {
    const std::string value = text.substr(axis.size() + 1);
    char* end = nullptr;
    const double v = std::strtod(value.c_str(), &end);
    if (value.empty() || *end != '\0' || !std::isfinite(v))
      throw Error("bad cut '" + text + "': '" + value + "' is not a number");
    cut.value = v;
  }
  return cut;
}

Box3 scene_bounds(const ParticleSet& particles, const Mesh* shell) {
  Box3 box = particles.bounds();
  if (shell)
    for (const Vec3& p : shell->positions) box.add(p);
  return box;
}

Camera frame_camera(const Box3& box_in, View view, double aspect) {
  Box3 box = box_in;
  if (box.empty()) {
    box.add(Vec3(-1, -1, -1));
    box.add(Vec3(1, 1, 1));
  }
  Camera camera;
  Vec3 towards_eye;
  view_direction(view, towards_eye, camera.up);
  camera.target = box.centre();
  const Vec3 back = normalize(towards_eye);
  const Vec3 right = normalize(cross(camera.up, back));
  const Vec3 up = cross(back, right);
  const double tan_v = std::tan(camera.vertical_fov_degrees * kPi / 360);
  const double tan_h = tan_v * std::max(aspect, 1e-3);
  // The closest distance from the target at which every corner of the box
  // projects inside the picture: corner c at depth z (towards the eye) and
  // offsets x, y needs |x| <= (d - z) tan_h and |y| <= (d - z) tan_v.
  const double extent = std::max(box.diagonal(), 1e-12);
  double distance = 0;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 c((corner & 1) ? box.hi.x : box.lo.x, (corner & 2) ? box.hi.y : box.lo.y,
                 (corner & 4) ? box.hi.z : box.lo.z);
    const Vec3 d = c - camera.target;
    const double z = dot(d, back);
    distance = std::max({distance, z + std::abs(dot(d, right)) / tan_h, z + std::abs(dot(d, up)) / tan_v,
                         z + 0.05 * extent});
  }
  distance *= 1.06;  // margin
  camera.eye = camera.target + back * distance;
  return camera;
}

}  // namespace pfill
