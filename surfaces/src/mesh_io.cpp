// OpenMesh is confined to this file (its headers are heavy and its IO registers writers globally).
#include "geartopo/surfaces/triangle_mesh.hpp"
#include "geartopo/files/atomic_write.hpp"

// MeshIO must come before the mesh kernel header (OpenMesh requirement).
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <string>

namespace geartopo::surfaces {
namespace {

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

} // namespace

bool is_mesh_extension(const std::filesystem::path& file) {
  static const std::array<std::string, 4> known{".ply", ".obj", ".stl", ".off"};
  return std::find(known.begin(), known.end(), lower_extension(file)) != known.end();
}

void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& file) {
  if (!is_mesh_extension(file))
    throw std::runtime_error(file.string() + ": unknown mesh format '" + file.extension().string() +
                             "' (use .ply, .obj, .stl or .off)");
  const bool with_values = mesh.vertex_values.size() == mesh.vertices.cols() && mesh.vertex_values.size() > 0;

  OMesh om;
  std::vector<OMesh::VertexHandle> vh;
  vh.reserve(static_cast<size_t>(mesh.vertices.cols()));
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i)
    vh.push_back(om.add_vertex(OMesh::Point(mesh.vertices(0, i), mesh.vertices(1, i), mesh.vertices(2, i))));
  for (Eigen::Index f = 0; f < mesh.faces.cols(); ++f) {
    const auto fh = om.add_face(vh[mesh.faces(0, f)], vh[mesh.faces(1, f)], vh[mesh.faces(2, f)]);
    if (!fh.is_valid()) throw std::runtime_error(file.string() + ": face " + std::to_string(f) + " is not manifold");
  }

  OpenMesh::IO::Options opts;
  const std::string ext = lower_extension(file);
  if (ext == ".ply" || ext == ".stl") opts += OpenMesh::IO::Options::Binary;
  OpenMesh::VPropHandleT<float> values;
  if (with_values && ext == ".ply") {
    om.add_property(values, mesh.value_name.empty() ? "value" : mesh.value_name);
    om.property(values).set_persistent(true);
    for (Eigen::Index i = 0; i < mesh.vertex_values.size(); ++i)
      om.property(values, vh[static_cast<size_t>(i)]) = static_cast<float>(mesh.vertex_values(i));
    opts += OpenMesh::IO::Options::Custom;
  }
  // OpenMesh writes to a path: a temporary beside the file (same extension, so the same format), renamed when complete.
  output::write_atomically_via_path(file, [&](const std::filesystem::path& tmp) {
    // OpenMesh reports progress on its own streams (stdout for some writers): keep our stdout for our output.
    omout().disable();
    omlog().disable();
    const bool ok = OpenMesh::IO::write_mesh(om, tmp.string(), opts);
    omout().enable();
    omlog().enable();
    if (!ok) throw output::OutputError(file, "OpenMesh could not write the mesh (is the folder writable? a full disk?)");
  });
}

} // namespace geartopo::surfaces
