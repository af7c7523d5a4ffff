// The proximity set of one frame, as an IPC solver asks for it every iteration: the C++
// wrapper.
//
//     proximity_cpp MESH DHAT
//
// Reads MESH and prints how many primitive pairs are closer than DHAT, per kind, twice on the
// same Ccd (built, then refitted), and the closest vertex-face pair.
#include <topoccd.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s MESH DHAT\n", argv[0]);
    return 2;
  }
  try {
    const auto mesh = topoccd::Mesh::read(argv[1]);
    const auto options = topoccd::ProximityOptions().dhat(std::atof(argv[2]));
    topoccd::Ccd ccd;
    for (int iteration = 0; iteration < 2; iteration++) {
      const auto p = ccd.proximity(mesh.positions(), mesh.triangles(), options);
      std::printf("iteration %d: %zu vf, %zu ee, %zu ve, %zu vv (%s)\n", iteration,
                  p.vf().size(), p.ee().size(), p.ve().size(), p.vv().size(),
                  p.refitted() ? "refitted" : "built");
      if (iteration == 1 && !p.vf().empty()) {
        const auto& c = *std::min_element(
            p.vf().begin(), p.vf().end(),
            [](const auto& a, const auto& b) { return a.distance < b.distance; });
        std::printf("closest vertex-face: vertex %u, face %u, distance %.6g, type %u\n", c.vertex,
                    c.face, c.distance, c.type);
      }
    }
  } catch (const topoccd::Error& e) {
    std::fprintf(stderr, "error: %s (%s)\n", e.what(), e.status_name());
    return 2;
  }
  return 0;
}
