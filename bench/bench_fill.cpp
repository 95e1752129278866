// bench_fill: whole fills of the reference meshes at the radii where the
// clipped hexagonal lattice packs 3,626 (spot) and 3,643 (bunny) spheres,
// plus the built-in torus; prints count, packing fraction, containment,
// overlaps and wall time against the lattice anchors, as text and JSON.
//
//   bench_fill [--mesh spot|bunny|torus|all] [--seeds N] [--stop-compare]
//              [--device SPEC] [--json FILE]
//   bench_fill --scale [--sizes 4000,16000,64000,100000] [--repeat R] [--mesh spot|bunny|torus]
//              [--sites N] [--birth-every K] [--sort-every S] [--no-profile] [--device SPEC] [--json FILE]
//
// --stop-compare fills spot once per stopping signal (blocked, ke,
// collisions) and reports what each gives.
//
// --scale fills one mesh (spot by default) at each count of --sizes (-n),
// each in a child process of its own so that its peak memory (RSS) is its
// own, and prints time (wall and CPU), steps and seconds per pass, packing, largest
// overlap, containment and peak memory per count, then the exponent of
// time against the count (least squares over log-log, and between
// neighbouring sizes). --repeat R runs the sizes R times over, in turn
// (each size meets the machine's slow and fast phases alike), and fits the
// fastest run of each (the fills are the same each time: a shared machine
// only ever slows one down). --sites / --birth-every run another birth schedule
// (e.g. --sites 2 --birth-every 3, the schedule before births in waves);
// --sort-every S renumbers the particles along the cells every S steps of
// the passes before the finish (FillOptions::sort_every; 0: never).
// --scale profiles each fill's queue (PFILL_PROFILE=1; --no-profile: not)
// and adds a line per count: the share of the time past the field that the
// device was busy (kernels and transfers), and per pass its steps, seconds,
// and kernel, transfer and host seconds.
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

using namespace pfill;

namespace {

struct Case {
  std::string name;
  std::string file;        // under the shared meshes, or "" for built-in
  double radius;           // in the file's units
  size_t lattice_count;    // the clipped lattice's count (0: none known)
  double lattice_packing;
};

const Case kCases[] = {
    {"spot", "spot.obj", 0.030160, 3626, 0.580},
    {"bunny", "stanford-bunny-closed.obj", 0.012253, 3643, 0.583},
    {"torus", "", 0.0, 0, 0},
};

nlohmann::ordered_json run_case(const Case& c, const Mesh& mesh, uint64_t seed, StopCriterion stop,
                                const std::string& device) {
  FillOptions o;
  if (c.radius > 0) o.radius = c.radius;
  else o.count = 4000;
  o.seed = seed;
  o.stop = stop;
  o.device = device;
  o.colour = ColourOptions{ColourMode::None, {}};
  const auto t0 = std::chrono::steady_clock::now();
  const FillResult r = fill(mesh, o);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const PackingMetrics& m = r.metrics;
  std::printf("%-6s seed %-3llu stop %-10s | %5zu spheres  phi %.4f  inside %6.2f%%  pen %5.2f%%r  "
              "overlap max %5.2f%%r mean %5.2f%%r | %6.1fs (field %.1fs) %8llu steps %7.0f steps/s | %s",
              c.name.c_str(), static_cast<unsigned long long>(seed), to_string(stop), m.count, m.packing_fraction,
              100 * m.contained_share, 100 * m.max_penetration, 100 * m.max_overlap, 100 * m.mean_overlap, wall,
              r.field_seconds, static_cast<unsigned long long>(r.steps), r.steps / std::max(1e-9, wall - r.field_seconds),
              r.stop_signal.c_str());
  if (c.lattice_count)
    std::printf("  (lattice %zu / %.3f: %+.1f%%)", c.lattice_count, c.lattice_packing,
                100.0 * (static_cast<double>(m.count) / c.lattice_count - 1));
  std::printf("\n");
  std::fflush(stdout);
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (const PassStats& p : r.passes) passes.push_back({{"pass", p.name}, {"steps", p.steps}, {"seconds", p.seconds}});
  return {{"mesh", c.name},
          {"radius", r.radius},
          {"seed", seed},
          {"stop", to_string(stop)},
          {"stop_signal", r.stop_signal},
          {"count", m.count},
          {"packing_fraction", m.packing_fraction},
          {"contained_share", m.contained_share},
          {"max_penetration", m.max_penetration},
          {"max_overlap", m.max_overlap},
          {"mean_overlap", m.mean_overlap},
          {"coordination", m.mean_coordination},
          {"max_parts", r.max_parts},
          {"finish_removed", r.finish_removed},
          {"holes_filled", r.holes_filled},
          {"containment_removed", r.containment.removed},
          {"lattice_count", c.lattice_count},
          {"lattice_packing", c.lattice_packing},
          {"seconds", wall},
          {"field_seconds", r.field_seconds},
          {"steps", r.steps},
          {"passes", passes},
          {"device", r.device}};
}

struct ScaleRun {
  size_t asked = 0;
  nlohmann::ordered_json figures;
};

/// One fill of `mesh` at about `count` particles, in a child process (the
/// parent never opens OpenCL, so the fork is safe): the child sends its
/// figures back as one line of JSON, peak RSS included.
nlohmann::ordered_json scale_fill(const Mesh& mesh, size_t count, int sites, int birth_every, int sort_every,
                                  const std::string& device, bool profile) {
  int fds[2];
  if (pipe(fds) != 0) throw Error("bench_fill: cannot make a pipe");
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) throw Error("bench_fill: cannot fork");
  if (pid == 0) {
    close(fds[0]);
    if (profile) setenv("PFILL_PROFILE", "1", 1);  // the fill's queue profiles: per-pass device times
    nlohmann::ordered_json j;
    try {
      FillOptions o;
      o.count = count;
      o.sites = sites;
      o.birth_every = birth_every;
      if (sort_every >= 0) o.sort_every = sort_every;
      o.device = device;
      o.colour = ColourOptions{ColourMode::None, {}};
      const auto t0 = std::chrono::steady_clock::now();
      const FillResult r = fill(mesh, o);
      const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      rusage ru{};  // CPU time (the peak memory is the fill's own: FillResult::peak_memory)
      getrusage(RUSAGE_SELF, &ru);
      nlohmann::ordered_json passes = nlohmann::ordered_json::array();
      double busy = 0;
      bool profiled = false;
      for (const PassStats& p : r.passes) {
        passes.push_back(pass_json(p));
        if (p.kernel_seconds >= 0) {  // PFILL_PROFILE=1 (the default of --scale)
          busy += p.kernel_seconds + p.transfer_seconds;
          profiled = true;
        }
      }
      const PackingMetrics& m = r.metrics;
      j = {{"asked", count},
           {"count", m.count},
           {"radius", r.radius},
           {"sites", r.sites.size()},
           {"seconds", wall},
           {"field_seconds", r.field_seconds},
           {"steps", r.steps},
           {"passes", passes},
           {"packing_fraction", m.packing_fraction},
           {"max_overlap", m.max_overlap},
           {"largest_hole", m.largest_hole},
           {"contained_share", m.contained_share},
           {"max_penetration", m.max_penetration},
           {"max_parts", r.max_parts},
           {"finish_removed", r.finish_removed},
           {"holes_filled", r.holes_filled},
           {"stop_signal", r.stop_signal},
           {"peak_rss_mib", r.peak_memory / 1048576.0},
           {"cpu_seconds", ru.ru_utime.tv_sec + ru.ru_stime.tv_sec + 1e-6 * (ru.ru_utime.tv_usec + ru.ru_stime.tv_usec)},
           {"device", r.device}};
      // The share of the fill's time past the field that the device spent
      // in kernels and transfers (the rest: the host's work between them,
      // site choice, the exact check).
      if (profiled) j["device_busy"] = busy / std::max(1e-9, wall - r.field_seconds);
    } catch (const std::exception& e) {
      j = {{"asked", count}, {"error", e.what()}};
    }
    const std::string line = j.dump() + "\n";
    ssize_t off = 0;
    while (off < static_cast<ssize_t>(line.size())) {
      const ssize_t w = write(fds[1], line.data() + off, line.size() - off);
      if (w <= 0) break;
      off += w;
    }
    close(fds[1]);
    _exit(0);
  }
  close(fds[1]);
  std::string text;
  char buf[4096];
  for (ssize_t got; (got = read(fds[0], buf, sizeof buf)) > 0;) text.append(buf, static_cast<size_t>(got));
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (text.empty()) throw Error("bench_fill: the fill of " + std::to_string(count) + " particles died");
  return nlohmann::ordered_json::parse(text);
}

std::vector<size_t> parse_sizes(const std::string& text) {
  std::vector<size_t> sizes;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const long long v = std::atoll(item.c_str());
    if (v <= 0) throw Error("--sizes '" + text + "': give counts separated by commas, e.g. 4000,16000");
    sizes.push_back(static_cast<size_t>(v));
  }
  if (sizes.empty()) throw Error("--sizes: give at least one count");
  return sizes;
}

double pass_steps(const nlohmann::ordered_json& j, const std::string& name) {
  for (const auto& p : j["passes"])
    if (p["pass"] == name) return p["steps"].get<double>();
  return 0;
}

double pass_seconds(const nlohmann::ordered_json& j, const std::string& name) {
  for (const auto& p : j["passes"])
    if (p["pass"] == name) return p["seconds"].get<double>();
  return 0;
}

// " (N rebuilt)": the steps of a pass that rebuilt the lists, where counted.
std::string rebuilt_on(const nlohmann::ordered_json& pass) {
  if (!pass.contains("list_rebuilds")) return "";
  return " (" + std::to_string(pass["list_rebuilds"].get<int64_t>()) + " rebuilt)";
}

void print_scale_row(size_t n, const nlohmann::ordered_json& j) {
  std::printf("| %zu | %zu | %.1f | %.1f | %.1f | %.0f (%.1f) | %.0f | %.0f (%.1f) | %.4f | %.3f%% r | %.2f r | %.2f%% | %.0f MiB |\n",
              n, j["count"].get<size_t>(), j["seconds"].get<double>(), j["cpu_seconds"].get<double>(),
              j["field_seconds"].get<double>(), pass_steps(j, "pass 1"), pass_seconds(j, "pass 1"),
              pass_steps(j, "settle"), pass_steps(j, "finish"), pass_seconds(j, "finish"),
              j["packing_fraction"].get<double>(), 100 * j["max_overlap"].get<double>(), j["largest_hole"].get<double>(),
              100 * j["contained_share"].get<double>(), j["peak_rss_mib"].get<double>());
  if (j.contains("device_busy")) {  // the profile: per pass, kernels, transfers, host
    std::printf("|   | device busy %.0f%% of the time past the field:", 100 * j["device_busy"].get<double>());
    for (const auto& p : j["passes"])
      if (p.contains("kernel_seconds"))
        std::printf(" %s %.0f steps%s %.2f s (kernels %.2f, transfers %.2f, host %.2f);",
                    p["pass"].get<std::string>().c_str(), p["steps"].get<double>(), rebuilt_on(p).c_str(),
                    p["seconds"].get<double>(), p["kernel_seconds"].get<double>(), p["transfer_seconds"].get<double>(),
                    p["host_seconds"].get<double>());
    std::printf(" |\n");
    // where each pass's kernel seconds went, the largest first
    for (const auto& p : j["passes"]) {
      if (!p.contains("kernels") || p["kernels"].empty()) continue;
      std::vector<std::pair<double, std::string>> split;
      for (const auto& [name, s] : p["kernels"].items()) split.push_back({s.get<double>(), name});
      std::sort(split.rbegin(), split.rend());
      std::printf("|   | %s kernels:", p["pass"].get<std::string>().c_str());
      for (const auto& [s, name] : split) std::printf(" %s %.2f s;", name.c_str(), s);
      std::printf(" |\n");
    }
  }
  std::fflush(stdout);
}

nlohmann::ordered_json run_scale(const Case& c, const Mesh& mesh, const std::vector<size_t>& sizes, int repeat,
                                 int sites, int birth_every, int sort_every, const std::string& device, bool profile) {
  std::printf("scale: %s, sites %s, birth every %s\n", c.name.c_str(),
              sites >= 0 ? std::to_string(sites).c_str() : "auto",
              birth_every ? std::to_string(birth_every).c_str() : "auto");
  std::printf("| -n | spheres | time s | CPU s | field s | pass 1 steps (s) | settle steps | finish steps (s) "
              "| packing | largest overlap | largest hole | inside | peak RSS |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  std::fflush(stdout);
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  std::vector<nlohmann::ordered_json> fastest(sizes.size());
  for (int round = 0; round < repeat; ++round)
    for (size_t k = 0; k < sizes.size(); ++k) {
      const nlohmann::ordered_json j = scale_fill(mesh, sizes[k], sites, birth_every, sort_every, device, profile);
      all.push_back(j);
      if (j.contains("error")) {
        std::printf("| %zu | failed: %s |\n", sizes[k], j["error"].get<std::string>().c_str());
        continue;
      }
      print_scale_row(sizes[k], j);
      if (fastest[k].is_null() || j["seconds"].get<double>() < fastest[k]["seconds"].get<double>()) fastest[k] = j;
    }
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  std::vector<double> xs, ys, cpu;
  if (repeat > 1) std::printf("fastest of %d runs of each size:\n", repeat);
  for (size_t k = 0; k < sizes.size(); ++k) {
    if (fastest[k].is_null()) continue;
    const nlohmann::ordered_json& j = fastest[k];
    const size_t n = sizes[k];
    runs.push_back(j);
    if (repeat > 1) print_scale_row(n, j);
    xs.push_back(std::log(static_cast<double>(n)));
    ys.push_back(std::log(j["seconds"].get<double>()));
    cpu.push_back(std::log(j["cpu_seconds"].get<double>()));
  }
  nlohmann::ordered_json out{{"mesh", c.name}, {"sites", sites}, {"birth_every", birth_every}, {"repeat", repeat},
                             {"runs", runs}};
  if (repeat > 1) out["all_runs"] = all;
  if (xs.size() >= 2) {
    double mx = 0, my = 0;
    for (size_t i = 0; i < xs.size(); ++i) mx += xs[i] / xs.size(), my += ys[i] / xs.size();
    double sxy = 0, sxx = 0;
    for (size_t i = 0; i < xs.size(); ++i) sxy += (xs[i] - mx) * (ys[i] - my), sxx += (xs[i] - mx) * (xs[i] - mx);
    const double exponent = sxx > 0 ? sxy / sxx : 0;
    std::printf("time ~ N^%.2f (least squares over %zu sizes)", exponent, xs.size());
    for (size_t i = 1; i < xs.size(); ++i)
      std::printf("; %.0f -> %.0f: x%.2f time for x%.2f particles (N^%.2f)", std::exp(xs[i - 1]), std::exp(xs[i]),
                  std::exp(ys[i] - ys[i - 1]), std::exp(xs[i] - xs[i - 1]), (ys[i] - ys[i - 1]) / (xs[i] - xs[i - 1]));
    std::printf("\n");
    out["exponent"] = exponent;
    double cxy = 0, cmy = 0;
    for (double c : cpu) cmy += c / cpu.size();
    for (size_t i = 0; i < xs.size(); ++i) cxy += (xs[i] - mx) * (cpu[i] - cmy);
    std::printf("CPU time ~ N^%.2f (least squares; on a shared machine steadier than the wall time)\n",
                sxx > 0 ? cxy / sxx : 0);
    out["cpu_exponent"] = sxx > 0 ? cxy / sxx : 0;
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all", json_path, device;
  int seeds = 1;
  bool stop_compare = false, scale = false, profile = true;
  std::vector<size_t> sizes{4000, 16000, 64000, 100000};
  int sites = -1, birth_every = 0, sort_every = -1, repeat = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw Error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--mesh") which = value();
    else if (a == "--seeds") seeds = std::stoi(value());
    else if (a == "--json") json_path = value();
    else if (a == "--device") device = value();
    else if (a == "--stop-compare") stop_compare = true;
    else if (a == "--scale") scale = true;
    else if (a == "--no-profile") profile = false;
    else if (a == "--sizes") sizes = parse_sizes(value());
    else if (a == "--repeat") repeat = std::max(1, std::stoi(value()));
    else if (a == "--sites") sites = std::stoi(value());
    else if (a == "--birth-every") birth_every = std::stoi(value());
    else if (a == "--sort-every") sort_every = std::stoi(value());
    else {
      std::fprintf(stderr, "usage: bench_fill [--mesh spot|bunny|torus|all] [--seeds N] [--stop-compare] "
                           "[--device SPEC] [--json FILE]\n"
                           "       bench_fill --scale [--sizes 4000,16000,64000,100000] [--repeat R] [--mesh spot|bunny|torus] "
                           "[--sites N] [--birth-every K] [--sort-every S] [--no-profile] [--device SPEC] [--json FILE]\n");
      return 2;
    }
  }
  if (scale && which == "all") which = "spot";
  const std::filesystem::path shared = PFILL_SHARED_MESHES;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  try {
    for (const Case& c : kCases) {
      if (which != "all" && which != c.name) continue;
      Mesh mesh;
      if (c.file.empty()) {
        mesh = make_builtin(c.name);
      } else if (std::filesystem::exists(shared / c.file)) {
        mesh = load_mesh((shared / c.file).string());
      } else {
        std::printf("%-6s skipped: %s not found\n", c.name.c_str(), (shared / c.file).c_str());
        continue;
      }
      if (scale) {
        runs.push_back(run_scale(c, mesh, sizes, repeat, sites, birth_every, sort_every, device, profile));
        continue;
      }
      for (int s = 1; s <= seeds; ++s) runs.push_back(run_case(c, mesh, s, StopCriterion::Blocked, device));
      if (stop_compare && c.name == "spot")
        for (StopCriterion stop : {StopCriterion::KineticEnergy, StopCriterion::Collisions})
          runs.push_back(run_case(c, mesh, 1, stop, device));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fill: %s\n", e.what());
    return 1;
  }
  if (!json_path.empty()) {
    std::ofstream(json_path) << nlohmann::ordered_json{{"bench", scale ? "fill_scale" : "fill"}, {"runs", runs}}.dump(2)
                             << "\n";
    std::printf("wrote %s\n", json_path.c_str());
  }
  return 0;
}
