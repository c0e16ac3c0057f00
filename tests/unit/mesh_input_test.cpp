// Stage 1, mesh_input.h: every refusal of validate_mesh with its status and a
// message naming the element; boundary_vertices.
#include "core/mesh_input.h"
#include "test_meshes.h"

#include <gtest/gtest.h>

#include <array>
#include <limits>

namespace developable {
namespace {

// The status validate_mesh throws (Status::ok when it accepts the mesh), and
// its message.
std::pair<Status, std::string> validation(const Positions& p, const Triangles& t) {
  try {
    validate_mesh(p, t);
  } catch (const EngineError& e) {
    return {e.status(), e.what()};
  }
  return {Status::ok, ""};
}

Triangles rows(std::initializer_list<std::array<int, 3>> list) {
  Triangles t(static_cast<Eigen::Index>(list.size()), 3);
  Eigen::Index f = 0;
  for (const auto& r : list) t.row(f++) << r[0], r[1], r[2];
  return t;
}

// Four vertices of a unit square, two triangles.
Positions square() {
  Positions p(4, 3);
  p << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
  return p;
}

TEST(MeshInput, AcceptsValidMeshes) {
  for (const auto& m : {test::plane(), test::cylinder(), test::cone(), test::cube()})
    EXPECT_EQ(validation(m.positions, m.triangles).first, Status::ok);
}

TEST(MeshInput, EmptyInput) {
  EXPECT_EQ(validation(Positions(0, 3), rows({{0, 1, 2}})).first, Status::empty_input);
  EXPECT_EQ(validation(square(), Triangles(0, 3)).first, Status::empty_input);
}

TEST(MeshInput, IndexOutOfRangeNamesTheTriangle) {
  const auto [status, message] = validation(square(), rows({{0, 1, 2}, {0, 2, 4}}));
  EXPECT_EQ(status, Status::index_out_of_range);
  EXPECT_NE(message.find("triangle 1"), std::string::npos) << message;
  EXPECT_EQ(validation(square(), rows({{0, -1, 2}})).first, Status::index_out_of_range);
}

TEST(MeshInput, NonFiniteCoordinateNamesTheVertex) {
  for (double bad : {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
    Positions p = square();
    p(2, 1) = bad;
    const auto [status, message] = validation(p, rows({{0, 1, 2}, {0, 2, 3}}));
    EXPECT_EQ(status, Status::non_finite_coordinate);
    EXPECT_NE(message.find("vertex 2"), std::string::npos) << message;
  }
}

TEST(MeshInput, DegenerateTriangles) {
  EXPECT_EQ(validation(square(), rows({{0, 1, 1}})).first, Status::degenerate_triangle);
  Positions p(3, 3);
  p << 0, 0, 0, 1, 0, 0, 2, 0, 0;  // collinear
  EXPECT_EQ(validation(p, rows({{0, 1, 2}})).first, Status::degenerate_triangle);
  // The sliver threshold is relative: a valid triangle stays valid at 1e-60.
  // (Below ~1e-77 the squared lengths inside norm() underflow.)
  Positions tiny = square() * 1e-60;
  EXPECT_EQ(validation(tiny, rows({{0, 1, 2}, {0, 2, 3}})).first, Status::ok);
}

TEST(MeshInput, DuplicateTriangleInAnyOrder) {
  const auto [status, message] = validation(square(), rows({{0, 1, 2}, {0, 2, 3}, {2, 0, 1}}));
  EXPECT_EQ(status, Status::duplicate_triangle);
  EXPECT_NE(message.find("triangle 2"), std::string::npos) << message;
}

TEST(MeshInput, NonManifoldEdgeAndVertex) {
  // Three triangles on edge (0, 1), in either winding: the edge is named.
  Positions p(5, 3);
  p << 0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1;
  for (const Triangles& fin : {rows({{0, 1, 2}, {1, 0, 3}, {0, 1, 4}}), rows({{0, 1, 2}, {0, 1, 3}, {0, 1, 4}})}) {
    const auto [status, message] = validation(p, fin);
    EXPECT_EQ(status, Status::non_manifold);
    EXPECT_NE(message.find("edge (0, 1) is shared by 3 triangles"), std::string::npos) << message;
  }
  // Two fans touching at vertex 0 (a bow tie), in either winding.
  Positions bow(5, 3);
  bow << 0, 0, 0, 1, 0, 0, 1, 1, 0, -1, 0, 0, -1, -1, 0;
  for (const Triangles& tie : {rows({{0, 1, 2}, {0, 3, 4}}), rows({{0, 1, 2}, {0, 4, 3}})}) {
    const auto [status, message] = validation(bow, tie);
    EXPECT_EQ(status, Status::non_manifold);
    EXPECT_NE(message.find("vertex 0 is non-manifold"), std::string::npos) << message;
  }
  // A fan round vertex 4 whose link is one chain, wound any way, is manifold.
  Positions fan(5, 3);
  fan << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 0.2;
  EXPECT_EQ(validation(fan, rows({{0, 1, 4}, {2, 1, 4}, {2, 3, 4}, {3, 0, 4}})).first, Status::ok);
  EXPECT_EQ(validation(fan, rows({{0, 1, 4}, {2, 1, 4}, {2, 3, 4}})).first, Status::ok);
}

TEST(MeshInput, EitherWindingIsAccepted) {
  // Neighbours that run edge (0, 2) the same way: once refused as an
  // inconsistent orientation, now the engine's to turn (orientation.h).
  EXPECT_EQ(validation(square(), rows({{0, 1, 2}, {0, 2, 3}})).first, Status::ok);
  EXPECT_EQ(validation(square(), rows({{0, 1, 2}, {3, 2, 0}})).first, Status::ok);
  // A one-sided band: three quads round a triangle, the last one joined with
  // half a twist (a Möbius strip), whatever the winding.
  Positions band(6, 3);
  band << 1, 0, 0, 1, 0, 1, -0.5, 0.87, 0, -0.5, 0.87, 1, -0.5, -0.87, 0, -0.5, -0.87, 1;
  EXPECT_EQ(validation(band, rows({{0, 2, 3}, {0, 3, 1}, {2, 4, 5}, {2, 5, 3}, {4, 1, 0}, {4, 0, 5}})).first,
            Status::ok);
}

TEST(MeshInput, UnusedVerticesAreAllowed) {
  Positions p(5, 3);
  p << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 7, 7, 7;
  EXPECT_EQ(validation(p, rows({{0, 1, 2}, {0, 2, 3}})).first, Status::ok);
}

TEST(MeshInput, BoundaryOfAGridIsItsRim) {
  const int r = 5, c = 6;
  const auto m = test::plane(r, c);
  const auto boundary = boundary_vertices(m.positions, m.triangles);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < c; ++j)
      EXPECT_EQ(boundary[i * c + j], i == 0 || j == 0 || i == r - 1 || j == c - 1) << i << "," << j;
  const auto closed = test::cube();
  for (bool b : boundary_vertices(closed.positions, closed.triangles)) EXPECT_FALSE(b);
}

TEST(MeshInput, StatusNamesAreDistinct) {
  EXPECT_STREQ(status_name(Status::non_manifold), "non_manifold");
  EXPECT_STREQ(status_name(Status::no_interior_vertex), "no_interior_vertex");
}

}  // namespace
}  // namespace developable
