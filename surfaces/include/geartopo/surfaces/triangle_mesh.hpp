// geartopo — a plain triangle mesh, the exchange type between geometry code and mesh files.
// OpenMesh stays inside mesh_io.cpp; callers see Eigen matrices only. Units: mm.
#pragma once

#include <Eigen/Core>

#include <filesystem>
#include <string>

namespace geartopo::surfaces {

struct TriangleMesh {
  Eigen::Matrix3Xd vertices;     ///< 3×V, positions (mm)
  Eigen::Matrix3Xi faces;        ///< 3×F, vertex indices, counter-clockwise seen from outside (normals out)
  Eigen::VectorXd vertex_values; ///< V or empty: one scalar per vertex (e.g. deviation in µm)
  std::string value_name;        ///< property name of vertex_values in PLY files (e.g. "deviation_um")
};

/// Writes .ply (binary), .obj, .stl (binary) or .off, chosen by the extension, through OpenMesh.
/// vertex_values are stored as a float vertex property in PLY files only.
/// Throws std::runtime_error naming the file when the extension is unknown or writing fails.
void write_mesh(const TriangleMesh& mesh, const std::filesystem::path& file);

/// Mesh file extensions write_mesh understands, lower case with the dot.
bool is_mesh_extension(const std::filesystem::path& file);

/// Signed volume (mm³) by the divergence theorem: positive when a closed mesh's faces point outwards.
double signed_volume(const TriangleMesh& mesh);

} // namespace geartopo::surfaces
