// Fills a shape with a few hundred spheres through pfill's C++ API and
// prints what came out: the consumer example of the CMake package.
//
//   pfill_consumer [MESH_FILE | sphere | cube | torus] [COUNT]
#include <cstdio>
#include <cstdlib>
#include <string>

#include "pfill/error.hpp"
#include "pfill/fill.hpp"
#include "pfill/fill_report.hpp"
#include "pfill/mesh_io.hpp"
#include "pfill/shapes.hpp"

int main(int argc, char** argv) {
  const std::string source = argc > 1 ? argv[1] : "sphere";
  try {
    bool builtin = false;
    for (const std::string& name : pfill::builtin_shape_names()) builtin = builtin || name == source;
    const pfill::Mesh mesh = builtin ? pfill::make_builtin(source) : pfill::load_mesh(source);

    pfill::FillOptions options;
    options.count = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 300;
    options.seed = 1;
    const pfill::FillResult result = pfill::fill(mesh, options);

    std::printf("filled %s with %zu particles of radius %g\n", mesh.source.c_str(), result.particles.size(),
                result.radius);
    std::printf("%s\n", pfill::metrics_json(result.metrics).dump().c_str());
    return result.particles.empty() ? 1 : 0;
  } catch (const pfill::Error& e) {
    std::fprintf(stderr, "pfill_consumer: error: %s\n", e.what());
    return 1;
  }
}
