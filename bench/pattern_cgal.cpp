// CGAL's Surface_mesh_parameterization (ARAP and LSCM, free border) on an OFF
// disc: prints the seconds and the max/mean |l_flat/l_3d - 1| after scaling the
// map to the 3D area (LSCM's map is free up to a similarity). Built and run by
// bench/pattern_cgal.py (needs Debian's libcgal-dev, only for this):
//   g++ -O2 -DNDEBUG -std=c++17 -I/usr/include/eigen3 -DCGAL_EIGEN3_ENABLED \
//       bench/pattern_cgal.cpp -o build/bin/pattern_cgal -lgmp -lmpfr
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/ARAP_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>
#include <CGAL/Surface_mesh_parameterization/parameterize.h>
#include <chrono>
#include <fstream>
#include <iostream>

using K = CGAL::Simple_cartesian<double>;
using Mesh = CGAL::Surface_mesh<K::Point_3>;
using VD = boost::graph_traits<Mesh>::vertex_descriptor;
using HD = boost::graph_traits<Mesh>::halfedge_descriptor;
namespace SMP = CGAL::Surface_mesh_parameterization;

template <typename P>
void run(const Mesh& input, const char* name) {
  Mesh mesh = input;
  auto uv = mesh.add_property_map<VD, K::Point_2>("v:uv").first;
  const HD border = CGAL::Polygon_mesh_processing::longest_border(mesh).first;
  const auto start = std::chrono::steady_clock::now();
  const auto status = SMP::parameterize(mesh, P(), border, uv);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  double a3 = 0, a2 = 0;
  for (auto f : mesh.faces()) {
    std::vector<VD> v;
    for (auto x : vertices_around_face(mesh.halfedge(f), mesh)) v.push_back(x);
    a3 += std::sqrt(CGAL::squared_area(mesh.point(v[0]), mesh.point(v[1]), mesh.point(v[2])));
    a2 += std::abs(CGAL::area(uv[v[0]], uv[v[1]], uv[v[2]]));
  }
  const double s = std::sqrt(a3 / a2);
  double worst = 0, sum = 0;
  long n = 0;
  for (auto h : mesh.halfedges()) {
    if (mesh.is_border(h)) continue;
    const double l3 = std::sqrt(CGAL::squared_distance(mesh.point(mesh.source(h)), mesh.point(mesh.target(h))));
    const double l2 = s * std::sqrt(CGAL::squared_distance(uv[mesh.source(h)], uv[mesh.target(h)]));
    const double e = std::abs(l2 / l3 - 1);
    worst = std::max(worst, e), sum += e, ++n;
  }
  std::cout << name << " status " << status << " seconds " << seconds << " max " << worst << " mean " << sum / n
            << std::endl;
}

int main(int argc, char** argv) {
  Mesh mesh;
  std::ifstream in(argv[1]);
  in >> mesh;
  run<SMP::LSCM_parameterizer_3<Mesh>>(mesh, "cgal_lscm");
  run<SMP::ARAP_parameterizer_3<Mesh>>(mesh, "cgal_arap");
}
