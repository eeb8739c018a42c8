#include "libs/textile/grid_mesh.h"

#include <cmath>
#include <stdexcept>

namespace haptex::textile {

GridMesh::GridMesh(const GridSpec& spec) : nu_(spec.particles_warp), nv_(spec.particles_weft) {
  if (!(std::isfinite(spec.length_warp_m) && spec.length_warp_m > 0.0)) {
    throw std::invalid_argument("GridSpec.length_warp_m must be finite and > 0");
  }
  if (!(std::isfinite(spec.width_weft_m) && spec.width_weft_m > 0.0)) {
    throw std::invalid_argument("GridSpec.width_weft_m must be finite and > 0");
  }
  if (nu_ < 2 || nv_ < 2) {
    throw std::invalid_argument("GridSpec needs at least 2 particles along warp and weft");
  }
  const double du = spec.length_warp_m / (nu_ - 1);
  const double dv = spec.width_weft_m / (nv_ - 1);
  rest_uv_m_.reserve(static_cast<std::size_t>(nu_ * nv_));
  std::vector<Mesh::VertexHandle> vh;
  vh.reserve(static_cast<std::size_t>(nu_ * nv_));
  for (int j = 0; j < nv_; ++j) {
    for (int i = 0; i < nu_; ++i) {
      rest_uv_m_.emplace_back(i * du, j * dv);
      vh.push_back(mesh_.add_vertex(Mesh::Point(static_cast<float>(i * du),
                                                static_cast<float>(j * dv), 0.0f)));
    }
  }
  // Alternate the diagonal cell by cell so the triangulation has no preferred bias direction.
  for (int j = 0; j + 1 < nv_; ++j) {
    for (int i = 0; i + 1 < nu_; ++i) {
      const int p00 = Index(i, j), p10 = Index(i + 1, j), p01 = Index(i, j + 1),
                p11 = Index(i + 1, j + 1);
      if ((i + j) % 2 == 0) {
        triangles_.push_back({p00, p10, p11});
        triangles_.push_back({p00, p11, p01});
      } else {
        triangles_.push_back({p00, p10, p01});
        triangles_.push_back({p10, p11, p01});
      }
    }
  }
  for (const auto& t : triangles_) {
    mesh_.add_face(vh[static_cast<std::size_t>(t[0])], vh[static_cast<std::size_t>(t[1])],
                   vh[static_cast<std::size_t>(t[2])]);
  }
}

bool GridMesh::IsBorder(int p) const { return mesh_.is_boundary(mesh_.vertex_handle(
    static_cast<unsigned int>(p))); }

std::vector<int> GridMesh::OneRing(int p) const {
  std::vector<int> ring;
  const auto v = mesh_.vertex_handle(static_cast<unsigned int>(p));
  for (auto it = mesh_.cvv_iter(v); it.is_valid(); ++it) ring.push_back(it->idx());
  return ring;
}

std::vector<int> GridMesh::BorderParticles() const {
  std::vector<int> out;
  for (int p = 0; p < num_particles(); ++p) {
    if (IsBorder(p)) out.push_back(p);
  }
  return out;
}

std::vector<Hinge> GridMesh::Hinges() const {
  std::vector<Hinge> out;
  for (const auto e : mesh_.edges()) {
    if (mesh_.is_boundary(e)) continue;
    const auto h0 = mesh_.halfedge_handle(e, 0);
    const auto h1 = mesh_.halfedge_handle(e, 1);
    Hinge hinge;
    hinge.c = mesh_.from_vertex_handle(h0).idx();
    hinge.d = mesh_.to_vertex_handle(h0).idx();
    hinge.a = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h0)).idx();
    hinge.b = mesh_.to_vertex_handle(mesh_.next_halfedge_handle(h1)).idx();
    out.push_back(hinge);
  }
  return out;
}

}  // namespace haptex::textile
