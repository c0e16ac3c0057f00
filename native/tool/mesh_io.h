// Mesh files for the command-line tool, through OpenMesh's readers and writers
// (OBJ, OFF, PLY, STL, chosen by the file extension).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace developable_tool {

// A mesh exactly as the file lists it: no face is dropped or repaired, so the
// engine's input check can name what is wrong with it. Polygons are split into
// fans of triangles; `polygon_of_triangle` maps each triangle to its polygon.
struct RawMesh {
  std::vector<double> positions;   // 3 per vertex
  std::vector<int32_t> triangles;  // 3 per triangle
  std::vector<int64_t> polygon_of_triangle;
  int64_t vertex_count() const { return static_cast<int64_t>(positions.size() / 3); }
  int64_t triangle_count() const { return static_cast<int64_t>(triangles.size() / 3); }
};

// Reads `path`. Returns false and sets `error` when the format is unknown or
// the file cannot be read.
bool read_raw_mesh(const std::string& path, RawMesh& mesh, std::string& error);

// Writes the triangles exactly as given, in their order and winding (also an
// inconsistently wound or one-sided result, which no OpenMesh mesh holds);
// OBJ with 17 significant digits, OFF, PLY and STL through OpenMesh's writers
// (single precision). Returns false and sets `error` when the file cannot be
// written; writes to a temporary file first and renames it, so no partial
// file is ever left.
bool write_mesh(const std::string& path, const std::vector<double>& positions, const std::vector<int32_t>& triangles,
                std::string& error);

// True when the extension names a format OpenMesh can write.
bool can_write(const std::string& path);

}  // namespace developable_tool
