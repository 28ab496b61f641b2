#include "cw4d/section/provenance.hpp"

#include <algorithm>
#include <string>

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/index.hpp"

namespace cw4d {

namespace {

// splitmix64's finaliser: every input bit reaches every output bit.
std::uint64_t mix(std::uint64_t h, std::uint64_t v) {
  std::uint64_t z = h ^ (v + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2));
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

const char* rank_name(int rank) {
  switch (rank) {
    case 0:
      return "vertex";
    case 1:
      return "edge";
    case 2:
      return "face";
    case 3:
      return "cell";
    default:
      return "element";
  }
}

std::string plural(int rank) {
  switch (rank) {
    case 0:
      return "vertices";
    case 1:
      return "edges";
    case 2:
      return "faces";
    case 3:
      return "cells";
    default:
      return "elements of rank " + std::to_string(rank);
  }
}

std::string fvector_text(const Complex& c) {
  std::string s = "(";
  for (int r = 0; r <= c.top_rank(); ++r) s += (r ? ", " : "") + std::to_string(c.count(r));
  return s + ")";
}

class Checker {
 public:
  Checker(const std::vector<const Complex*>& models, bool scene) : models_(models), scene_(scene) {}

  const Complex& model(std::uint32_t object) const {
    if (object >= models_.size() || models_[object] == nullptr)
      throw InputError("the section was not cut from this scene (object id " +
                       std::to_string(object) + " >= " + std::to_string(models_.size()) +
                       " objects)");
    return *models_[object];
  }

  // Model element `id` of rank `rank` (of object `object`).
  void element(std::uint32_t object, int rank, std::uint32_t id) const {
    const Complex& m = model(object);
    const std::size_t count = rank <= m.top_rank() ? m.count(rank) : 0;
    if (id < count) return;
    throw InputError(std::string("the section was not cut from this ") +
                     (scene_ ? "scene (object " + std::to_string(object) + ": " : "model (") +
                     rank_name(rank) + " id " + std::to_string(id) +
                     " >= " + std::to_string(count) + " " + plural(rank) + ")");
  }

  void vertex(std::uint32_t object, const VertexSource& v) const {
    if (v.rank == 1 && v.element == no_index) return;  // a tetrahedralization's diagonal
    if (v.rank > 1)
      throw InputError("the section was not cut from a model (a vertex source of rank " +
                       std::to_string(v.rank) + ")");
    element(object, v.rank, v.element);
  }

 private:
  const std::vector<const Complex*>& models_;
  bool scene_;
};

}  // namespace

std::uint64_t model_fingerprint(const Complex& model) {
  std::uint64_t h = mix(0x63773464ULL, static_cast<std::uint64_t>(model.ambient_dim()));
  h = mix(h, static_cast<std::uint64_t>(model.top_rank()));
  for (int r = 0; r <= model.top_rank(); ++r) h = mix(h, model.count(r));
  return h ? h : 1;
}

std::uint64_t models_fingerprint(const std::vector<const Complex*>& models) {
  if (models.size() == 1) return model_fingerprint(*models.front());
  std::uint64_t h = mix(0x7363656eULL, models.size());
  for (const Complex* m : models) h = mix(h, model_fingerprint(*m));
  return h ? h : 1;
}

void check_provenance(const Section& section, const Complex& model) {
  check_provenance(section, std::vector<const Complex*>{&model});
}

void check_provenance(const Section& section, const std::vector<const Complex*>& models) {
  if (models.empty()) throw InputError("the section's provenance needs the model it was cut from");
  if (std::find(models.begin(), models.end(), nullptr) != models.end())
    throw InputError("the section's provenance needs every model of its scene");
  const Complex& c = section.complex;
  const std::size_t nf = c.top_rank() >= 2 ? c.count(2) : 0;
  const bool scene = section.object_of_face.size() == nf && nf > 0;
  if (section.source_fingerprint != 0 && section.source_fingerprint != models_fingerprint(models))
    throw InputError(
        models.size() == 1
            ? "the section was not cut from this model (its f-vector " +
                  fvector_text(*models.front()) + " is not the one of the section's source)"
            : "the section was not cut from these " + std::to_string(models.size()) +
                  " models (their f-vectors are not the ones of the section's sources)");
  for (const Complex* m : models)
    if (m->ambient_dim() != c.ambient_dim() + 1)
      throw InputError("the section was not cut from this model (the section lives in R^" +
                       std::to_string(c.ambient_dim()) + ", the model in R^" +
                       std::to_string(m->ambient_dim()) + ")");
  const Checker check(models, scene);
  const bool vertices = section.vertex_source.size() == c.count(0);
  if (!scene) {
    // One model: every id of every rank against it, the cells (the ids readers index most)
    // first so that the message names a cell when cells are out of range.
    std::vector<std::size_t> ranks;
    if (section.source.size() > 2) ranks.push_back(2);
    for (std::size_t k = 1; k < section.source.size(); ++k)
      if (k != 2) ranks.push_back(k);
    for (std::size_t k : ranks)
      if (static_cast<int>(k) <= c.top_rank() && section.source[k].size() == c.count(k))
        for (std::uint32_t id : section.source[k]) check.element(0, static_cast<int>(k) + 1, id);
    if (vertices)
      for (const VertexSource& v : section.vertex_source) check.vertex(0, v);
    return;
  }
  // A scene: each face's ids (its cell, its edges' model faces, its vertices' model vertices or
  // edges) against the model of its object; ranks above the faces against every model.
  const bool cells = section.source.size() > 2 && section.source[2].size() == nf;
  const bool edges = section.source.size() > 1 && section.source[1].size() == c.count(1);
  for (std::uint32_t f = 0; f < nf; ++f) {
    const std::uint32_t object = section.object_of_face[f];
    check.model(object);
    if (cells) check.element(object, 3, section.source[2][f]);
    if (edges)
      for (std::uint32_t e : c.boundary(2).ids(f)) check.element(object, 2, section.source[1][e]);
    if (vertices)
      for (std::uint32_t v : c.vertices_of(2, f)) check.vertex(object, section.vertex_source[v]);
  }
  for (std::size_t k = 3; k < section.source.size(); ++k) {
    if (static_cast<int>(k) > c.top_rank() || section.source[k].size() != c.count(k)) continue;
    for (std::uint32_t id : section.source[k]) {
      bool some = false;
      for (const Complex* m : models)
        some = some || (static_cast<int>(k) + 1 <= m->top_rank() && id < m->count(k + 1));
      if (!some) check.element(0, static_cast<int>(k) + 1, id);
    }
  }
}

}  // namespace cw4d
