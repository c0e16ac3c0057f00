// Connectivity benchmark (issue 14): the engine's vertex -> faces table
// (native/mesh_connectivity.h) against OpenMesh's halfedge mesh built from
// the same triangles, on closed grid tori of the given face counts. Prints
// one JSON object per line: faces, vertices, which structure, build_ms
// (median of --repeats builds) and faces_visited (a checksum: every face of
// every vertex's ring walked once, so both structures answer the same
// question). Built with -DDEVELOPABLE_CONNECTIVITY_BENCH=ON.
//   connectivity_bench [--repeats N] FACES...
#include "core/mesh_connectivity.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace {

using Clock = std::chrono::steady_clock;
using OpenMeshTriMesh = OpenMesh::TriMesh_ArrayKernelT<>;

// A closed grid torus with about `faces` triangles (rows x cols cells).
developable::Triangles torus(int faces, int& vertices) {
  const int cols = std::max(3, static_cast<int>(std::sqrt(faces / 2.0)));
  const int rows = std::max(3, faces / (2 * cols));
  vertices = rows * cols;
  developable::Triangles t(2 * rows * cols, 3);
  int f = 0;
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j) {
      const int a = i * cols + j, b = i * cols + (j + 1) % cols;
      const int c = ((i + 1) % rows) * cols + j, d = ((i + 1) % rows) * cols + (j + 1) % cols;
      t.row(f++) << a, b, d;
      t.row(f++) << a, d, c;
    }
  return t;
}

template <typename Build>
double median_ms(int repeats, Build&& build, long long& checksum) {
  std::vector<double> ms;
  for (int r = 0; r < repeats; ++r) {
    const auto start = Clock::now();
    checksum = build();
    ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
  }
  std::nth_element(ms.begin(), ms.begin() + ms.size() / 2, ms.end());
  return ms[ms.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int repeats = 5;
  std::vector<int> sizes;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--repeats" && i + 1 < argc)
      repeats = std::atoi(argv[++i]);
    else
      sizes.push_back(std::atoi(argv[i]));
  }
  if (sizes.empty()) sizes = {10000, 100000, 1000000};
  for (const int faces : sizes) {
    int vertices = 0;
    const developable::Triangles t = torus(faces, vertices);
    long long engine_sum = 0, openmesh_sum = 0;
    const double engine_ms = median_ms(
        repeats,
        [&] {
          const developable::VertexFaces table = developable::vertex_faces(t, vertices);
          long long sum = 0;
          for (int v = 0; v < vertices; ++v) sum += table.count(v);
          return sum;
        },
        engine_sum);
    const double openmesh_ms = median_ms(
        repeats,
        [&] {
          OpenMeshTriMesh mesh;
          std::vector<OpenMeshTriMesh::VertexHandle> handles(static_cast<size_t>(vertices));
          for (auto& h : handles) h = mesh.add_vertex(OpenMeshTriMesh::Point(0, 0, 0));
          for (Eigen::Index f = 0; f < t.rows(); ++f)
            mesh.add_face(handles[t(f, 0)], handles[t(f, 1)], handles[t(f, 2)]);
          long long sum = 0;
          for (const auto v : mesh.vertices())
            for (auto it = mesh.cvf_iter(v); it.is_valid(); ++it) ++sum;
          return sum;
        },
        openmesh_sum);
    std::printf(
        "{\"faces\": %lld, \"vertices\": %d, \"structure\": \"engine vertex_faces\", \"build_ms\": %.3f, "
        "\"faces_visited\": %lld}\n",
        static_cast<long long>(t.rows()), vertices, engine_ms, engine_sum);
    std::printf(
        "{\"faces\": %lld, \"vertices\": %d, \"structure\": \"OpenMesh TriMesh\", \"build_ms\": %.3f, "
        "\"faces_visited\": %lld}\n",
        static_cast<long long>(t.rows()), vertices, openmesh_ms, openmesh_sum);
  }
  return 0;
}
