#include "mesh_io.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/exporter/BaseExporter.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/Mesh/BaseKernel.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>

namespace developable_tool {
namespace {

using namespace OpenMesh;

// Records vertices and faces as the reader sees them. OpenMesh's own importer
// silently drops faces that would make the mesh non-manifold; this one keeps
// them so that the engine reports the problem instead of hiding it.
class RawImporter : public IO::BaseImporter {
 public:
  explicit RawImporter(RawMesh& mesh) : mesh_(mesh) {}

  VertexHandle add_vertex(const Vec3f& p) override { return add_vertex(Vec3d(p)); }
  VertexHandle add_vertex(const Vec3d& p) override {
    mesh_.positions.insert(mesh_.positions.end(), {p[0], p[1], p[2]});
    return VertexHandle(static_cast<int>(mesh_.vertex_count() - 1));
  }
  VertexHandle add_vertex() override { return add_vertex(Vec3d(0.0, 0.0, 0.0)); }
  FaceHandle add_face(const VHandles& polygon) override {
    // Fans keep the polygon's orientation. A face with fewer than three
    // corners becomes a degenerate triangle, which the engine then names.
    auto corner = [&](size_t i) { return polygon.empty() ? -1 : polygon[std::min(i, polygon.size() - 1)].idx(); };
    const size_t fans = polygon.size() < 3 ? 1 : polygon.size() - 2;
    for (size_t i = 1; i <= fans; ++i) {
      mesh_.triangles.insert(mesh_.triangles.end(), {corner(0), corner(i), corner(i + 1)});
      mesh_.polygon_of_triangle.push_back(polygons_);
    }
    return FaceHandle(static_cast<int>(polygons_++));
  }
  size_t n_vertices() const override { return static_cast<size_t>(mesh_.vertex_count()); }
  size_t n_faces() const override { return static_cast<size_t>(polygons_); }
  size_t n_edges() const override { return 0; }

  // Everything else a reader may hand over (normals, colours, texture
  // coordinates, half-edge structure) is not used by the engine.
  HalfedgeHandle add_edge(VertexHandle, VertexHandle) override { return HalfedgeHandle(); }
  FaceHandle add_face(HalfedgeHandle) override { return FaceHandle(); }
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec2f>&) override {}
  void add_face_texcoords(FaceHandle, VertexHandle, const std::vector<Vec3f>&) override {}
  void set_face_texindex(FaceHandle, int) override {}
  void set_point(VertexHandle v, const Vec3f& p) override {
    if (v.idx() >= 0 && v.idx() < mesh_.vertex_count())
      for (int a = 0; a < 3; ++a) mesh_.positions[3 * static_cast<size_t>(v.idx()) + a] = p[a];
  }
  void set_halfedge(VertexHandle, HalfedgeHandle) override {}
  void set_normal(VertexHandle, const Vec3f&) override {}
  void set_normal(VertexHandle, const Vec3d&) override {}
  void set_color(VertexHandle, const Vec3uc&) override {}
  void set_color(VertexHandle, const Vec4uc&) override {}
  void set_color(VertexHandle, const Vec3f&) override {}
  void set_color(VertexHandle, const Vec4f&) override {}
  void set_texcoord(VertexHandle, const Vec2f&) override {}
  void set_status(VertexHandle, const Attributes::StatusInfo&) override {}
  void set_next(HalfedgeHandle, HalfedgeHandle) override {}
  void set_face(HalfedgeHandle, FaceHandle) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HalfedgeHandle, const Vec2f&) override {}
  void set_texcoord(VertexHandle, const Vec3f&) override {}
  void set_texcoord(HalfedgeHandle, const Vec3f&) override {}
  void set_status(HalfedgeHandle, const Attributes::StatusInfo&) override {}
  void set_color(EdgeHandle, const Vec3uc&) override {}
  void set_color(EdgeHandle, const Vec4uc&) override {}
  void set_color(EdgeHandle, const Vec3f&) override {}
  void set_color(EdgeHandle, const Vec4f&) override {}
  void set_status(EdgeHandle, const Attributes::StatusInfo&) override {}
  void set_normal(FaceHandle, const Vec3f&) override {}
  void set_normal(FaceHandle, const Vec3d&) override {}
  void set_color(FaceHandle, const Vec3uc&) override {}
  void set_color(FaceHandle, const Vec4uc&) override {}
  void set_color(FaceHandle, const Vec3f&) override {}
  void set_color(FaceHandle, const Vec4f&) override {}
  void set_status(FaceHandle, const Attributes::StatusInfo&) override {}
  void add_texture_information(int, std::string) override {}

 private:
  RawMesh& mesh_;
  int64_t polygons_ = 0;
};

// Hands OpenMesh's writers the triangles exactly as the engine returned them.
// An OpenMesh mesh cannot hold them all: its add_face refuses a face whose
// edge a neighbour runs the same way ("complex edge"), and the engine runs
// inconsistently wound and one-sided meshes (orientation.h) and returns their
// faces in the caller's winding. The writers need only vertices and faces.
// Everything else is answered as OpenMesh's exporter of the PolyMesh with
// double points the tool wrote before (is_triangle_mesh stays false, which
// sets the OFF writer's spacing), so an orientable result's file is byte for
// byte as it was.
class RawExporter : public IO::BaseExporter {
 public:
  RawExporter(const std::vector<double>& positions, const std::vector<int32_t>& triangles)
      : positions_(positions), triangles_(triangles) {}

  Vec3d pointd(VertexHandle v) const override {
    const size_t i = 3 * static_cast<size_t>(v.idx());
    return Vec3d(positions_[i], positions_[i + 1], positions_[i + 2]);
  }
  Vec3f point(VertexHandle v) const override { return Vec3f(pointd(v)); }
  bool is_point_double() const override { return true; }
  unsigned int get_vhandles(FaceHandle f, std::vector<VertexHandle>& corners) const override {
    const size_t i = 3 * static_cast<size_t>(f.idx());
    corners = {VertexHandle(triangles_[i]), VertexHandle(triangles_[i + 1]), VertexHandle(triangles_[i + 2])};
    return 3;
  }
  size_t n_vertices() const override { return positions_.size() / 3; }
  size_t n_faces() const override { return triangles_.size() / 3; }
  size_t n_edges() const override { return 0; }
  // No custom properties: the PLY writer lists the kernel's.
  const BaseKernel* kernel() override { return &no_properties_; }

  // Nothing else is written: no normals (the STL writer computes each face's
  // from its corners), colours, texture coordinates, status or half-edges.
  Vec3f normal(VertexHandle) const override { return Vec3f(0.0f); }
  Vec3d normald(VertexHandle) const override { return Vec3d(0.0); }
  bool is_normal_double() const override { return true; }
  Vec3uc color(VertexHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(VertexHandle) const override { return Vec4uc(0); }
  Vec3ui colori(VertexHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(VertexHandle) const override { return Vec4ui(0); }
  Vec3f colorf(VertexHandle) const override { return Vec3f(0.0f); }
  Vec4f colorAf(VertexHandle) const override { return Vec4f(0.0f); }
  Vec2f texcoord(VertexHandle) const override { return Vec2f(0.0f); }
  Vec2f texcoord(HalfedgeHandle) const override { return Vec2f(0.0f); }
  Attributes::StatusInfo status(VertexHandle) const override { return {}; }
  HalfedgeHandle getHeh(FaceHandle, VertexHandle) const override { return HalfedgeHandle(); }
  unsigned int get_face_texcoords(std::vector<Vec2f>& texcoords) const override {
    texcoords.clear();
    return 0;
  }
  Vec3f normal(FaceHandle) const override { return Vec3f(0.0f); }
  Vec3d normald(FaceHandle) const override { return Vec3d(0.0); }
  Vec3uc color(FaceHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(FaceHandle) const override { return Vec4uc(0); }
  Vec3ui colori(FaceHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(FaceHandle) const override { return Vec4ui(0); }
  Vec3f colorf(FaceHandle) const override { return Vec3f(0.0f); }
  Vec4f colorAf(FaceHandle) const override { return Vec4f(0.0f); }
  Attributes::StatusInfo status(FaceHandle) const override { return {}; }
  Vec3uc color(EdgeHandle) const override { return Vec3uc(0); }
  Vec4uc colorA(EdgeHandle) const override { return Vec4uc(0); }
  Vec3ui colori(EdgeHandle) const override { return Vec3ui(0); }
  Vec4ui colorAi(EdgeHandle) const override { return Vec4ui(0); }
  Vec3f colorf(EdgeHandle) const override { return Vec3f(0.0f); }
  Vec4f colorAf(EdgeHandle) const override { return Vec4f(0.0f); }
  Attributes::StatusInfo status(EdgeHandle) const override { return {}; }
  int get_halfedge_id(VertexHandle) override { return -1; }
  int get_halfedge_id(FaceHandle) override { return -1; }
  int get_next_halfedge_id(HalfedgeHandle) override { return -1; }
  int get_to_vertex_id(HalfedgeHandle) override { return -1; }
  int get_face_id(HalfedgeHandle) override { return -1; }
  Attributes::StatusInfo status(HalfedgeHandle) const override { return {}; }

 private:
  const std::vector<double>& positions_;
  const std::vector<int32_t>& triangles_;
  BaseKernel no_properties_;
};

std::string extension(const std::string& path) {
  const size_t dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? std::string() : path.substr(dot + 1);
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

// The whitespace-separated words of one line of text (the C locale's
// blanks; the line ends at its '\n', which the caller has cut off).
class Words {
 public:
  Words(const char* begin, const char* end) : at_(begin), end_(end) {}

  // The next word, or an empty one at the end of the line.
  std::string_view next() {
    while (at_ < end_ && blank(*at_)) ++at_;
    const char* begin = at_;
    while (at_ < end_ && !blank(*at_)) ++at_;
    return {begin, static_cast<size_t>(at_ - begin)};
  }

 private:
  static bool blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

  const char* at_;
  const char* end_;
};

// `parse` (strtod, strtol) of a NUL-terminated copy of `word`: handed the
// text in place, they would be given the rest of the file, which a
// sanitizer's string checks read whole on every call.
template <class Parse>
auto parse_word(std::string_view word, const Parse& parse) {
  char buffer[64];
  if (word.size() >= sizeof(buffer)) return parse(std::string(word).c_str());
  std::memcpy(buffer, word.data(), word.size());
  buffer[word.size()] = '\0';
  return parse(static_cast<const char*>(buffer));
}

// OBJ is read here rather than by OpenMesh: its reader skips what it cannot
// parse ("nan" coordinates, faces with repeated or missing vertices) without
// telling, and the engine must see those to name them. Polygons become fans
// through the same importer as every other format. The file is read whole
// and split in place (a stream per line took 1.3 s of a 1M-face run).
bool read_obj(const std::string& path, RawImporter& importer, std::string& error) {
  std::ifstream in(path, std::ios::binary);
  std::string text;
  in.seekg(0, std::ios::end);
  text.resize(static_cast<size_t>(std::max<std::streamoff>(in.tellg(), 0)));
  in.seekg(0, std::ios::beg);
  in.read(text.data(), static_cast<std::streamsize>(text.size()));
  if (!in) {
    error = "cannot read " + path;
    return false;
  }
  const char* at = text.data();
  const char* const end = at + text.size();
  for (long line_number = 1; at < end; ++line_number) {
    const char* line_end = static_cast<const char*>(std::memchr(at, '\n', static_cast<size_t>(end - at)));
    if (line_end == nullptr) line_end = end;
    Words words(at, line_end);
    at = line_end + 1;
    const std::string_view keyword = words.next();
    if (keyword == "v") {
      Vec3d p;
      for (int a = 0; a < 3; ++a) {
        const std::string_view word = words.next();
        if (word.empty()) {
          error = path + ":" + std::to_string(line_number) + ": a vertex needs three coordinates";
          return false;
        }
        // strtod reads "nan" and "inf" too, so the engine can name them.
        p[a] = parse_word(word, [](const char* c) { return std::strtod(c, nullptr); });
      }
      importer.add_vertex(p);
    } else if (keyword == "f") {
      IO::BaseImporter::VHandles polygon;
      for (std::string_view corner = words.next(); !corner.empty(); corner = words.next()) {
        const long index = parse_word(corner, [](const char* c) { return std::strtol(c, nullptr, 10); });
        // Negative indices count back from the last vertex read so far.
        const long vertex = index < 0 ? static_cast<long>(importer.n_vertices()) + index : index - 1;
        polygon.push_back(VertexHandle(static_cast<int>(
            std::clamp<long>(vertex, std::numeric_limits<int>::min(), std::numeric_limits<int>::max()))));
      }
      importer.add_face(polygon);
    }
  }
  return true;
}

}  // namespace

bool read_raw_mesh(const std::string& path, RawMesh& mesh, std::string& error) {
  if (!std::ifstream(path).good()) {
    error = "cannot open " + path;
    return false;
  }
  const std::string ext = extension(path);
  if (ext != "obj" && ext != "off" && ext != "ply" && ext != "stl") {
    error = "unknown mesh format '." + extension(path) + "' (use .obj, .off, .ply or .stl)";
    return false;
  }
  mesh = RawMesh{};
  RawImporter importer(mesh);
  if (extension(path) == "obj") return read_obj(path, importer, error);
  // OpenMesh's log stream announces every file it touches; the tool reports itself.
  omlog().disable();
  IO::Options options;
  if (!IO::IOManager().read(path, importer, options)) {
    error = "cannot read " + path + " as a mesh";
    return false;
  }
  return true;
}

bool can_write(const std::string& path) { return IO::IOManager().can_write(extension(path)); }

// OBJ is written here so that coordinates keep all 17 digits; OpenMesh's
// writers go through single precision. Each line is formatted by to_chars
// (the text of printf's %.17g and %d, at a fraction of the time) into a
// buffer written in blocks.
bool write_obj(const std::string& path, const std::vector<double>& positions, const std::vector<int32_t>& triangles) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (file == nullptr) return false;
  bool ok = std::fprintf(file, "# developable: %zu vertices, %zu triangles\n", positions.size() / 3,
                         triangles.size() / 3) > 0;
  // Whole lines into `buffer`, written out a block at a time.
  constexpr size_t kBlock = 1 << 20;
  std::string buffer;
  char line[128];
  const auto end_line = [&](char* at) {
    *at++ = '\n';
    buffer.append(line, at);
    if (buffer.size() < kBlock) return;
    ok = ok && std::fwrite(buffer.data(), 1, buffer.size(), file) == buffer.size();
    buffer.clear();
  };
  for (size_t v = 0; v + 2 < positions.size(); v += 3) {
    char* at = line;
    *at++ = 'v';
    for (size_t k = v; k < v + 3; ++k) {
      *at++ = ' ';
      at = std::to_chars(at, line + sizeof(line), positions[k], std::chars_format::general, 17).ptr;
    }
    end_line(at);
  }
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    char* at = line;
    *at++ = 'f';
    for (size_t k = t; k < t + 3; ++k) {
      *at++ = ' ';
      at = std::to_chars(at, line + sizeof(line), triangles[k] + 1L).ptr;
    }
    end_line(at);
  }
  ok = ok && std::fwrite(buffer.data(), 1, buffer.size(), file) == buffer.size();
  return std::fclose(file) == 0 && ok;
}

bool write_mesh(const std::string& path, const std::vector<double>& positions, const std::vector<int32_t>& triangles,
                std::string& error) {
  if (extension(path) == "obj") {
    const std::string temporary = path + ".partial";
    if (!write_obj(temporary, positions, triangles) || std::rename(temporary.c_str(), path.c_str()) != 0) {
      std::remove(temporary.c_str());
      error = "cannot write " + path;
      return false;
    }
    return true;
  }
  RawExporter exporter(positions, triangles);
  // The extension decides the format: keep it on the temporary name.
  const std::string temporary = path + ".partial." + extension(path);
  const IO::Options options;
  omlog().disable();
  if (!IO::IOManager().write(temporary, exporter, options, 17)) {
    std::remove(temporary.c_str());
    error = "cannot write " + path;
    return false;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    error = "cannot move the result to " + path;
    return false;
  }
  return true;
}

}  // namespace developable_tool
