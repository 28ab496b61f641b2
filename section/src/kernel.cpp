#include "cw4d/section/slicer.hpp"

#include <Eigen/SVD>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <unordered_map>
#include <utility>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "cw4d/complex/error.hpp"
#include "cw4d/complex/fork_join.hpp"
#include "cw4d/complex/geometry.hpp"
#include "cw4d/complex/tolerances.hpp"
#include "general.hpp"
#include "slicer_detail.hpp"
#include "slicer_impl.hpp"

namespace cw4d {

// --- the R^4 kernel -----------------------------------------------------------------------

namespace {

// For each byte value m, the places of its set bits in increasing order, and their number.
struct ByteLists {
  std::uint8_t pos[256][8];
  std::uint8_t count[256];
};

constexpr ByteLists make_byte_lists() {
  ByteLists t{};
  for (int m = 0; m < 256; ++m) {
    int k = 0;
    for (int i = 0; i < 8; ++i)
      if ((m >> i) & 1) t.pos[m][k++] = static_cast<std::uint8_t>(i);
    t.count[m] = static_cast<std::uint8_t>(k);
  }
  return t;
}

constexpr ByteLists kByteLists = make_byte_lists();

// For each 4-bit value m, four signs as bytes in memory order: -1 where bit i of m is set.
constexpr std::array<std::array<std::int8_t, 4>, 16> make_sign_bytes() {
  std::array<std::array<std::int8_t, 4>, 16> t{};
  for (int m = 0; m < 16; ++m)
    for (int i = 0; i < 4; ++i) t[m][i] = static_cast<std::int8_t>((m >> i) & 1 ? -1 : 1);
  return t;
}

constexpr std::array<std::array<std::int8_t, 4>, 16> kSignBytes = make_sign_bytes();

// Writes x + pos[i] for the eight places pos[0..7] to list[0..7] (a word of marks lists its
// nonzero ones through the byte table: the places past their count are written and dropped).
inline void write_byte_positions_scalar(const std::uint8_t* pos, std::uint32_t x,
                                        std::uint32_t* list) {
  for (int i = 0; i < 8; ++i) list[i] = x + pos[i];
}

#if defined(__SSE2__)
// write_byte_positions_scalar with two 128-bit stores.
inline void write_byte_positions_sse2(const std::uint8_t* pos, std::uint32_t x,
                                      std::uint32_t* list) {
  const __m128i zero = _mm_setzero_si128();
  const __m128i p16 =
      _mm_unpacklo_epi8(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(pos)), zero);
  const __m128i base = _mm_set1_epi32(static_cast<int>(x));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(list),
                   _mm_add_epi32(_mm_unpacklo_epi16(p16, zero), base));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(list + 4),
                   _mm_add_epi32(_mm_unpackhi_epi16(p16, zero), base));
}
#endif

inline void write_byte_positions(const std::uint8_t* pos, std::uint32_t x, std::uint32_t* list) {
#if defined(__SSE2__)
  write_byte_positions_sse2(pos, x, list);
#else
  write_byte_positions_scalar(pos, x, list);
#endif
}

// The range [j0, j1) of element x's row of cofaces (up_ids): a fixed width known at compile time
// (Stride > 0), else the model's fixed width (stride, when nonzero) or its offsets.
template <std::uint32_t Stride>
inline void up_row(std::uint32_t x, std::uint32_t stride, const std::uint32_t* up_offsets,
                   std::uint32_t& j0, std::uint32_t& j1) {
  if constexpr (Stride > 0) {
    j0 = x * Stride, j1 = j0 + Stride;
  } else {
    j0 = stride ? x * stride : up_offsets[x];
    j1 = stride ? j0 + stride : up_offsets[x + 1];
  }
}

// Lists every x of [b, e) whose mark (a count of 0 to 3) is nonzero, in increasing x, zeroing
// the marks eight at a time; returns the new end of the list, and sets odd's low bits when a
// listed count is odd (1 or 3). Up to 8 entries past the new end may be written. A word of
// eight marks writes its eight places at once and advances past the nonzero ones (a table of
// byte values): no branch per mark (whether a face or cell is cut is unpredictable), and the
// work on the listed elements is then a plain loop over ids.
inline std::uint32_t* list_marks(std::uint8_t* marks, std::uint32_t b, std::uint32_t e,
                                 std::uint32_t* list, std::uint64_t& odd) {
  constexpr std::uint64_t kLow = 0x0101010101010101u;
  std::uint32_t x = b;
  for (; x < e && (x & 7u); ++x)
    if (marks[x]) odd |= marks[x] & 1u, *list++ = x, marks[x] = 0;
  for (; x + 8 <= e; x += 8) {
    std::uint64_t w;
    std::memcpy(&w, marks + x, 8);
    if (!w) continue;
    std::memset(marks + x, 0, 8);
    odd |= w & kLow;
    // One bit per nonzero mark (bit 1 of a count folded onto bit 0), gathered into a byte.
    const std::uint64_t nz = (w | (w >> 1)) & kLow;
    const unsigned mask = static_cast<unsigned>((nz * 0x0102040810204080u) >> 56);
    write_byte_positions(kByteLists.pos[mask], x, list);
    list += kByteLists.count[mask];
  }
  for (; x < e; ++x)
    if (marks[x]) odd |= marks[x] & 1u, *list++ = x, marks[x] = 0;
  return list;
}

// Lists the edges e0 <= e < e1 whose ends have different sides from list[count] on; returns the
// new count. Every edge is written and the count advanced past the crossing ones: no branch
// (which edges cross is unpredictable).
inline std::uint32_t list_crossings(const std::uint32_t* edge_ends, const Side* side,
                                    std::uint32_t e0, std::uint32_t e1, std::uint32_t* list,
                                    std::uint32_t count) {
  const std::uint32_t* ends = edge_ends + 2 * std::size_t{e0};
  std::uint32_t e = e0;
  // Four edges a round (the loop's own counting is then a quarter of the work per edge).
  for (; e + 4 <= e1; e += 4, ends += 8) {
    list[count] = e;
    count += side[ends[0]] != side[ends[1]];
    list[count] = e + 1;
    count += side[ends[2]] != side[ends[3]];
    list[count] = e + 2;
    count += side[ends[4]] != side[ends[5]];
    list[count] = e + 3;
    count += side[ends[6]] != side[ends[7]];
  }
  for (; e < e1; ++e, ends += 2) {
    list[count] = e;
    count += side[ends[0]] != side[ends[1]];
  }
  return count;
}

// The implied rows of nse section edges: offsets 2 i, signs -1, +1 (four edges' signs a word).
inline void write_edge_rows(std::uint32_t nse, std::uint32_t* off, std::int8_t* sg) {
  const std::size_t rows = std::size_t{nse} + 1;  // (a trip count that cannot wrap: vectorised)
  for (std::size_t i = 0; i < rows; ++i) off[i] = static_cast<std::uint32_t>(2 * i);
  const std::int8_t pairs[8] = {-1, 1, -1, 1, -1, 1, -1, 1};
  std::uint64_t word;
  std::memcpy(&word, pairs, 8);
  std::uint32_t i = 0;
  for (; i + 4 <= nse; i += 4) std::memcpy(sg + 2 * i, &word, 8);
  for (; i < nse; ++i) sg[2 * i] = -1, sg[2 * i + 1] = 1;
}

// Rank 1 of the kernel: the crossing of each listed edge (its section vertex v, in list order),
// handed to the faces above it with its coefficient in the face's cut (the top bit: +1); the
// faces' counts (face_count, up to 3) and their two crossings (face_ends). False when a
// crossing needs the general path (near_general: near an end or nearly parallel to the plane).
// Everything in locals: the byte stores of the counts would otherwise make the compiler reload
// every pointer kept in memory. Stride: the number of faces above every edge when it is known
// at compile time (the inner loop unrolls), else 0 (then `stride`, or the offsets, say).
// Capped: a face may have more than three edges, so its count is held at 3 (a count of 4 would
// read as an even, or as no, mark); else no face is handed more than three crossings.
template <std::uint32_t Stride, bool Capped, class CrossingTest>
bool hand_crossings(const std::uint32_t* list, std::uint32_t count, const std::uint32_t* edge_ends,
                    const Side* side, const double* s, const CrossingTest& near_general,
                    const std::uint32_t* edge_model, VertexSource* vs, std::uint32_t* vertex_edge,
                    const std::uint32_t* up_offsets, const std::uint32_t* up_ids,
                    std::uint32_t stride, std::uint8_t* face_count, std::uint32_t* face_ends,
                    std::uint32_t* pairs_out) {
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  std::uint32_t pairs = 0;
  for (std::uint32_t v = 0; v < count; ++v) {
    const std::uint32_t e = list[v];
    const std::uint32_t a = edge_ends[2 * e], b = edge_ends[2 * e + 1];
    const double t = s[a] / (s[a] - s[b]);
    if (near_general(a, b, s[a], s[b], t)) return false;  // as crossing()
    vs[v] = {edge_model ? edge_model[e] : e, 1, t};
    vertex_edge[v] = e;
    // The crossing's coefficient in the edge's cut is +1 when the tail is below; in a face's
    // cut that times the edge's sign there (the coface's top bit: -1).
    const std::uint32_t tail_above = side[a] == Side::Negative ? 0u : kFlip;
    const std::uint32_t entry = v | tail_above;  // (v < kFlip)
    std::uint32_t j0, j1;
    up_row<Stride>(e, stride, up_offsets, j0, j1);
    for (std::uint32_t j = j0; j < j1; ++j) {
      const std::uint32_t up = up_ids[j];
      const std::uint32_t f = up & kIndex;
      const std::uint32_t k = face_count[f];
      // (2 f is 2 up in 32 bits: the sign bit shifts out; k >= 2: fails below)
      face_ends[(up << 1) + (k & 1u)] = entry ^ (up & kFlip);
      if constexpr (Capped)
        face_count[f] = static_cast<std::uint8_t>(k < 3 ? k + 1 : 3);
      else
        face_count[f] = static_cast<std::uint8_t>(k + 1);
    }
    pairs += j1 - j0;
  }
  *pairs_out = pairs;
  return true;
}

// The polygon of a cut cell of at most W faces (faces[i] with sign signs[i] in the cell), in
// registers at a fixed width: each cut face (face_edge[f], its section edge, or no_index) is a
// step, forward (edge_row's tail to head) when the face's sign in the cell is -1; the loop is
// followed from the smallest tail and written to ids/signs (up to W entries; *added of them
// are the polygon's). False when the steps are not one loop through every step of at least
// three (a pinch, an open chain, several loops): the generic gathering decides those.
template <int W>
inline bool chain_fixed(const std::uint32_t* faces, const std::int8_t* signs, std::uint32_t nfaces,
                        const std::uint32_t* face_edge, const std::uint32_t* edge_row,
                        std::uint32_t* ids, std::int8_t* out_signs, std::uint32_t* added) {
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  constexpr std::uint32_t kNoTail = 0xffffffffu, kNoHead = 0xfffffffeu;  // (no vertex ids)
  std::uint32_t tails[W], heads[W], edge[W];
  std::uint32_t ns = 0;
  for (std::uint32_t i = 0; i < nfaces; ++i) {
    // Masks, not branches (which way a face goes, and whether it is cut, are unpredictable).
    const std::uint32_t se = face_edge[faces[i]];
    const std::uint32_t cut = se != no_index;
    const std::uint32_t r = se & (0u - cut);  // (written to the next slot, kept only when cut)
    const std::uint32_t fwd = static_cast<std::uint32_t>(static_cast<std::int32_t>(signs[i]) >> 31);
    const std::uint32_t a = edge_row[2 * r], b = edge_row[2 * r + 1];
    const std::uint32_t tail = b ^ ((a ^ b) & fwd);
    tails[ns] = tail;
    heads[ns] = a ^ b ^ tail;
    edge[ns] = r | (kFlip & ~fwd);
    ns += cut;
  }
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(W); ++i) {
    tails[i] = i < ns ? tails[i] : kNoTail;
    heads[i] = i < ns ? heads[i] : kNoHead;
    edge[i] = i < ns ? edge[i] : 0;
  }
  std::uint32_t lo = 0;
  bool bad = ns < 3;
  for (std::uint32_t i = 1; i < static_cast<std::uint32_t>(W); ++i) {
    lo = tails[i] < tails[lo] ? i : lo;
    for (std::uint32_t j = 0; j < i; ++j) bad |= tails[i] == tails[j] && i < ns;  // a pinch
  }
  std::uint32_t next[W];
  for (std::uint32_t i = 0; i < static_cast<std::uint32_t>(W); ++i) {
    std::uint32_t n = W;
    for (std::uint32_t j = 0; j < static_cast<std::uint32_t>(W); ++j)
      n = tails[j] == heads[i] ? j : n;
    next[i] = n;
  }
  // Walk W steps from lo (those past the ns-th are written and dropped); one loop through
  // every step returns to lo first after exactly ns steps, each step having a successor.
  std::uint32_t cur = lo, closed = 0;
  for (std::uint32_t k = 0; k < static_cast<std::uint32_t>(W); ++k) {
    ids[k] = edge[cur] & kIndex;
    out_signs[k] = (edge[cur] & kFlip) ? -1 : 1;
    const std::uint32_t n = next[cur];
    const bool live = k < ns;
    bad |= live && n == static_cast<std::uint32_t>(W);  // the chain does not close
    closed = live && closed == 0 && n == lo ? k + 1 : closed;
    cur = n < static_cast<std::uint32_t>(W) ? n : 0;
  }
  *added = ns;
  return !bad && closed == ns;
}

// A tetrahedron's polygon: the model's table (tet_cases, 16 entries per cell, decided when the
// model was compiled by the generic gathering's rules) for the sides of its four vertices tv;
// only its faces' section edges (face_edge of cell_faces) are read. Writes four entries (a
// triangle's fourth is dropped) and returns the polygon's length, 3 or 4, or 7 when the table
// leaves the cell to the generic gathering.
template <class SideT>
inline std::uint32_t tet_polygon(const std::uint32_t* tv, const std::uint16_t* tet_cases,
                                 const SideT* side, const std::uint32_t* cell_faces,
                                 const std::uint32_t* face_edge, std::uint32_t* ids,
                                 std::int8_t* signs) {
  // The kernel's sides are -1 or +1 (a vertex on the plane left the fast path): a side's sign
  // bit is set below, so the four sign bits give the vertices below, the complement of the
  // pattern.
  const auto below = [&](int k) {
    return static_cast<std::uint32_t>(static_cast<std::uint8_t>(side[tv[k]])) >> 7 << k;
  };
  const std::uint32_t pattern = (below(0) | below(1) | below(2) | below(3)) ^ 15u;
  const std::uint32_t code = tet_cases[pattern];
  for (std::uint32_t k = 0; k < 4; ++k) ids[k] = face_edge[cell_faces[(code >> (3 + 2 * k)) & 3u]];
  // The four signs (bits 11-14: -1) as four bytes at once.
  std::memcpy(signs, &kSignBytes[(code >> 11) & 15u], 4);
  return code & 7u;
}

// Phase 3 for a model of tetrahedra when nothing above the polygons is written per polygon: the
// polygon of each of the ncut listed cells from its table (tet_polygon; a tetrahedron's four
// faces are row 4 x of cell_faces), its offset, source and facet, in a loop of its own that
// keeps everything in registers. False when a table leaves a cell to the generic gathering.
inline bool tet_polygons(const std::uint32_t* visit, std::uint32_t ncut,
                         const std::uint32_t* tet_vertex, const std::uint16_t* tet_case,
                         const Side* side, const std::uint32_t* cell_faces,
                         const std::uint32_t* face_edge, const std::uint32_t* cell_model,
                         std::uint32_t* poly_ids, std::int8_t* poly_signs, std::uint32_t* poly_off,
                         std::uint32_t* src, std::uint32_t* facet, std::uint32_t* entries_out) {
  std::uint32_t entries = 0;
  for (std::uint32_t i = 0; i < ncut; ++i) {
    const std::uint32_t x = visit[i];
    const std::uint32_t added = tet_polygon(
        tet_vertex + 4 * std::size_t{x}, tet_case + 16 * std::size_t{x}, side,
        cell_faces + 4 * std::size_t{x}, face_edge, poly_ids + entries, poly_signs + entries);
    if (added == 7) return false;
    entries += added;
    poly_off[i + 1] = entries;
    src[i] = cell_model ? cell_model[x] : x;
    facet[i] = x;
  }
  *entries_out = entries;
  return true;
}

// The polygon of a cut cell of more than four faces from the ns steps its cut faces left in its
// bucket: each step is entered in a map by its tail (step, stamped with st so that the map is
// never cleared), then the loop is followed from the smallest tail and written to ids/signs
// (*added entries). False for a pinch (two steps from one vertex, or a face listed twice), an
// open chain, several loops or fewer than three steps: the generic gathering decides those.
template <class CellStepT, class LoopStepT>
inline bool chain_bucket(const CellStepT* cs, std::uint32_t ns, LoopStepT* step, std::uint32_t st,
                         std::uint32_t* ids, std::int8_t* signs, std::uint32_t* added) {
  constexpr std::uint32_t kIndex = 0x7fffffffu;
  std::uint32_t lo = 0xffffffffu;
  bool pinch = false;
  for (std::uint32_t k = 0; k < ns; ++k) {
    const CellStepT c = cs[k];
    pinch |= step[c.tail].stamp == st;
    step[c.tail] = {st, c.head, c.edge};
    lo = std::min(lo, c.tail);
  }
  bool ok = !pinch;
  ok = ok && ns >= 3;
  std::uint32_t cur = lo;
  for (std::uint32_t k = 0; ok;) {
    const LoopStepT sp = step[cur];
    if (sp.stamp != st) return false;  // the chain does not close
    ids[k] = sp.edge & kIndex;
    signs[k] =
        static_cast<std::int8_t>(static_cast<std::int32_t>(sp.edge) >> 31 | 1);  // (-1: kFlip)
    ++k;
    cur = sp.head;
    if (cur == lo) {
      *added = k;
      return k == ns;  // else several loops
    }
    ok = k < ns;
  }
  return false;
}

// Phase 3 for a model whose every cell has more than four faces (each chained from its bucket,
// chain_bucket) when nothing above the polygons is written per polygon: the ncut listed cells'
// polygons, offsets, sources and facets, in a loop of its own that keeps everything in
// registers. Cell i is stamped first_stamp + i (the caller makes sure that does not wrap).
// InPlace: each cell's bucket is at its row (cell_row) and holds taken[x] steps (reset to 0
// here), else it is from start[x] to fill[x]. False when a cell is left to the generic
// gathering.
template <bool InPlace, class CellStepT, class LoopStepT>
inline bool bucket_polygons(const std::uint32_t* visit, std::uint32_t ncut, const CellStepT* bucket,
                            const std::uint32_t* start, const std::uint32_t* fill,
                            const std::uint32_t* cell_row, std::uint32_t* taken, LoopStepT* step,
                            std::uint32_t first_stamp, const std::uint32_t* cell_model,
                            std::uint32_t* poly_ids, std::int8_t* poly_signs,
                            std::uint32_t* poly_off, std::uint32_t* src, std::uint32_t* facet,
                            std::uint32_t* entries_out) {
  std::uint32_t entries = 0;
  for (std::uint32_t i = 0; i < ncut; ++i) {
    const std::uint32_t x = visit[i];
    std::uint32_t added = 0, b, ns;
    if constexpr (InPlace) {
      b = cell_row[x], ns = taken[x];
      taken[x] = 0;
    } else {
      b = start[x], ns = fill[x] - start[x];
    }
    if (!chain_bucket(bucket + b, ns, step, first_stamp + i, poly_ids + entries,
                      poly_signs + entries, &added))
      return false;
    entries += added;
    poly_off[i + 1] = entries;
    src[i] = cell_model ? cell_model[x] : x;
    facet[i] = x;
  }
  *entries_out = entries;
  return true;
}
}  // namespace

// Rank 2 of the kernel: a face handed two crossings of opposite coefficients gives the section
// edge from the one with -1 to the one with +1; it keeps that edge's id for its cells and marks
// them, and (Buckets) hands each cell its step in the cell's bucket. Everything the loop reads
// and writes is in locals: the byte stores of the marks would otherwise make the compiler
// reload every pointer kept in memory.
struct Slicer::Impl::FaceHand {
  const std::uint32_t* faces;  // the cut faces, in increasing id
  std::uint32_t nse;
  const std::uint32_t* face_ends;  // per face its two crossings | coefficient bit
  std::uint32_t* edge_row;         // out: the section edges' ends
  std::uint32_t* src;              // out: their sources
  const std::uint32_t* face_model;
  std::uint32_t* face_edge;  // per face its section edge
  const std::uint32_t* up_offsets;
  const std::uint32_t* up_ids;
  std::uint32_t up_stride;
  std::uint8_t* cell_count;  // per cell its mark
  std::uint32_t* fill;       // per cell its bucket's next free step
  std::uint32_t* start;      // per cell its bucket's first step
  const std::uint32_t* cell_row;
  CellStep* bucket;
  std::size_t room;
  std::uint32_t* taken = nullptr;  // (in place) per cell the steps in its bucket at its row
  std::size_t placed = 0;          // steps placed in the buckets
  std::size_t want = 0;            // (when a face did not fit) the steps it needs placed
  std::uint32_t pairs = 0;         // (cut face, cell) pairs
  bool bad = false;
};

template <bool Buckets, bool RoomChecked, std::uint32_t Stride>
std::uint32_t Slicer::Impl::hand_faces(FaceHand& h, std::uint32_t se) {
  constexpr std::uint32_t kFlip = 0x80000000u, kIndex = 0x7fffffffu;
  const std::uint32_t* const faces = h.faces;
  const std::uint32_t nse = h.nse;
  const std::uint32_t* const face_ends = h.face_ends;
  std::uint32_t* const edge_row = h.edge_row;
  std::uint32_t* const src = h.src;
  const std::uint32_t* const face_model = h.face_model;
  std::uint32_t* const face_edge = h.face_edge;
  const std::uint32_t* const up_offsets = h.up_offsets;
  const std::uint32_t* const up_ids = h.up_ids;
  const std::uint32_t stride = h.up_stride;
  std::uint8_t* const cell_count = h.cell_count;
  std::uint32_t* const fill = h.fill;
  std::uint32_t* const start = h.start;
  const std::uint32_t* const cell_row = h.cell_row;
  CellStep* const bucket = h.bucket;
  const std::size_t room = h.room;
  std::uint32_t* const taken = h.taken;
  std::size_t placed = h.placed;
  std::uint32_t pairs = h.pairs;
  bool bad = h.bad;
  for (; se < nse; ++se) {
    const std::uint32_t x = faces[se];
    std::uint32_t j0, j1;
    up_row<Stride>(x, stride, up_offsets, j0, j1);
    if constexpr (Buckets && RoomChecked) {
      // Room for the rows of the cells this face is the first cut face of (counted before
      // anything is written, so that a face that does not fit is done whole after the growth).
      std::size_t need = 0;
      for (std::uint32_t j = j0; j < j1; ++j) {
        const std::uint32_t y = up_ids[j] & kIndex;
        need += cell_count[y] == 0 ? cell_row[y + 1] - cell_row[y] : 0u;
      }
      if (placed + need > room) {
        h.want = placed + need;
        break;
      }
    }
    const std::uint32_t p = face_ends[2 * x], q = face_ends[2 * x + 1];
    // Two crossings (no more, no fewer: an even count below 4), distinct, of opposite
    // coefficients.
    bad |= ((p ^ q) & kFlip) == 0 || ((p ^ q) & kIndex) == 0;
    const std::uint32_t tail = p ^ ((p ^ q) & (0u - (p >> 31)));  // (p's flip: q is the tail)
    const std::uint32_t ta = tail & kIndex, hd = (p ^ q ^ tail) & kIndex;
    edge_row[2 * se] = ta;
    edge_row[2 * se + 1] = hd;
    src[se] = face_model ? face_model[x] : x;
    face_edge[x] = se;
    for (std::uint32_t j = j0; j < j1; ++j) {
      const std::uint32_t up = up_ids[j];
      const std::uint32_t y = up & kIndex;
      if constexpr (Buckets) {
        std::uint32_t at;
        if constexpr (RoomChecked) {
          const bool first = cell_count[y] == 0;  // (selects, not branches)
          at = first ? static_cast<std::uint32_t>(placed) : fill[y];
          start[y] = first ? at : start[y];
          placed += first ? cell_row[y + 1] - cell_row[y] : 0u;
          fill[y] = at + 1;
        } else {
          // Room for every row: each cell's bucket is its own row's place.
          const std::uint32_t k = taken[y];
          taken[y] = k + 1;
          at = cell_row[y] + k;
        }
        // The step's sign is minus the face's sign in the cell: forward when that is -1.
        const std::uint32_t fwd = static_cast<std::uint32_t>(static_cast<std::int32_t>(up) >> 31);
        const std::uint32_t t = hd ^ ((ta ^ hd) & fwd);
        bucket[at] = {t, ta ^ hd ^ t, se | (kFlip & ~fwd)};
      }
      cell_count[y] = 1;
    }
    pairs += j1 - j0;
  }
  h.placed = placed;
  h.pairs = pairs;
  h.bad = bad;
  return se;
}

Slicer::Impl::KernelResult Slicer::Impl::kernel_slice(const SliceModel::Compiled& m,
                                                      const Placement& pl, SliceBuffers& out,
                                                      bool marked_edges) {
  // A section vertex per crossing edge, a section edge per face with exactly two crossings, a
  // polygon per cell whose section edges form one loop: the buffers the generic gathering
  // writes for such a slice (tested element for element), in the same order, written once.
  // No face gathers its crossings by reading its boundary: each crossing edge hands its section
  // vertex to the faces above it (coface lists carrying the edge's sign in the face), and a face
  // reads its two from one place. Each cut face keeps its section edge's id (face_edge_, reset
  // after the slice, or before the next one that is not of tetrahedra: a table reads only cut
  // faces' ids) and marks the cells above it; a cut cell reads its own faces' ids (a
  // tetrahedron only those its table names). The per-element counts double as the marks of the
  // faces and cells to visit (zero between slices: cleared when listed, or wholly when the
  // kernel stops half way).
  if (!m.unit_signs_) return KernelResult::Generic;  // multiplicities: the generic gathering
  start_kernel_buffers(m, pl, out);
  constexpr std::uint32_t kIndex = 0x7fffffffu;
  const SliceModel::Compiled::Rank& E = m.ranks_[1];
  const SliceModel::Compiled::Rank& F = m.ranks_[2];
  const SliceModel::Compiled::Rank& C = m.ranks_[3];
  const std::uint32_t* const edge_ends = E.ids.data();
  const Side* const side = side_.data();
  const double* const s = s_.data();
  const SliceModel::Compiled::CrossingTest needs_general = m.crossing_test(near_parallel_);
  const std::uint32_t* const edge_model = E.model_id.empty() ? nullptr : E.model_id.data();
  const std::uint32_t* const face_model = F.model_id.empty() ? nullptr : F.model_id.data();
  const std::uint32_t* const cell_model = C.model_id.empty() ? nullptr : C.model_id.data();
  const std::size_t nf = F.offsets.size() - 1, nc = C.offsets.size() - 1;
  if (face_mark_.size() < nf) face_mark_.resize(nf, 0);
  if (cell_mark_.size() < nc) cell_mark_.resize(nc, 0);
  if (face_ends_.size() < 2 * nf) face_ends_.resize(2 * nf);
  if (face_edge_.size() < nf) face_edge_.resize(nf, no_index);
  const bool tets = !m.tet_vertices_.empty();
  // Only the fixed-width chains (cells of up to four faces, not a table's) read every face's
  // section edge, uncut ones included: for them face_edge_ is kept at no_index between slices.
  // A table reads only cut faces' and bucket cells none: those slices leave it stale.
  const bool fixed_chains = !tets && m.small_cells_;
  if (fixed_chains && face_edge_stale_) {
    std::fill(face_edge_.begin(), face_edge_.end(), no_index);
    face_edge_stale_ = false;
  }
  std::uint8_t* const face_count = face_mark_.data();
  std::uint8_t* const cell_count = cell_mark_.data();
  std::uint32_t* const face_ends = face_ends_.data();
  // Cells that are not the tetrahedra of a table each collect their steps (one per cut face,
  // written by the face) in a bucket, so that a cut cell reads only its cut faces' steps, not
  // its whole row. A cell's first cut face places its bucket, with room for its whole row,
  // after the last one placed: the buckets take the cut cells' rows, not the model's.
  const bool buckets = m.tet_vertices_.empty();
  if (buckets && cell_fill_.size() < nc) {
    cell_fill_.resize(nc);
    cell_start_.resize(nc);
    cell_taken_.resize(nc, 0);
  }
  auto stop = [this](KernelResult result) {
    std::fill(face_mark_.begin(), face_mark_.end(), 0);
    std::fill(cell_mark_.begin(), cell_mark_.end(), 0);
    std::fill(face_edge_.begin(), face_edge_.end(), no_index);
    std::fill(cell_taken_.begin(), cell_taken_.end(), 0u);
    face_edge_stale_ = false;
    return result;
  };
  const SliceModel::Compiled::Up edge_up = m.up(1), face_up = m.up(2);
  const std::uint32_t* const edge_up_ids = edge_up.ids;
  const std::uint32_t* const face_up_ids = face_up.ids;
  // Phase 1, list_crossings + hand_crossings (rank 1): the crossings, in id order cluster by
  // cluster, each handed to its faces with its coefficient in the face's cut (the kFlip bit: +1).
  // The crossing edges of every touched cluster are listed first, without a branch (the sides are
  // unpredictable), or those a sweep marked; then the outputs are sized once.
  const std::size_t ne = E.count;
  if (crossing_ids_.size() < ne) crossing_ids_.resize(ne);
  std::uint32_t* const list = crossing_ids_.data();
  std::uint32_t count = 0;
  for (auto c : touched_) {
    const std::uint32_t e0 = m.begin_[0][c], e1 = m.begin_[0][c + 1];
    if (marked_edges) {
      visit_marked(mark_[1], e0, e1, [list, &count](std::uint32_t e) {
        list[count++] = e;
        return true;
      });
    } else {
      count = list_crossings(edge_ends, side, e0, e1, list, count);
    }
  }
  if (count == 0) {
    clear_to_empty(out, m.dim_ - 1);
    section_edge_.clear();
    facet_internal_.clear();
    return KernelResult::Done;
  }
  out.vertex_source.resize(count);
  section_edge_.resize(count);
  std::uint32_t cut_faces_bound = 0;
  // (three faces above every edge: three cells around each edge, as in the tesseract, the
  // 24-cell and the 120-cell; five: the 600-cell)
  using Test = SliceModel::Compiled::CrossingTest;
  const bool capped = !m.triangle_faces_;
  const auto hand = edge_up.stride == 3
                        ? (capped ? hand_crossings<3, true, Test> : hand_crossings<3, false, Test>)
                    : edge_up.stride == 5
                        ? (capped ? hand_crossings<5, true, Test> : hand_crossings<5, false, Test>)
                        : (capped ? hand_crossings<0, true, Test> : hand_crossings<0, false, Test>);
  if (!hand(list, count, edge_ends, side, s, needs_general, edge_model, out.vertex_source.data(),
            section_edge_.data(), edge_up.offsets, edge_up_ids, edge_up.stride, face_count,
            face_ends, &cut_faces_bound)) {
    reason_ = FallbackReason::Weld;
    return stop(KernelResult::General);
  }
  // Phase 2, list_marks + hand_faces (rank 2): a face handed two crossings of opposite coefficients
  // gives the section edge from the one with -1 to the one with +1; it keeps that edge's id for its
  // cells and marks them. (list_marks may write 8 entries past the listed ones)
  if (face_list_.size() < cut_faces_bound + 8) face_list_.resize(cut_faces_bound + 8);
  std::uint32_t* const faces = face_list_.data();
  std::uint32_t* faces_end = faces;
  std::uint64_t odd_count = 0;  // a face handed one crossing or more than two
  for (auto c : touched_)
    faces_end = list_marks(face_count, m.begin_[1][c], m.begin_[1][c + 1], faces_end, odd_count);
  const std::uint32_t nse = static_cast<std::uint32_t>(faces_end - faces);
  Incidence::Storage edges = out.boundary[0].storage();
  edges.ids.resize(2 * std::size_t{nse});
  edges.signs.resize(2 * std::size_t{nse});
  edges.offsets.resize(std::size_t{nse} + 1);
  out.source[1].resize(nse);
  std::uint32_t cut_cells_bound = 0;  // (cut face, cell) pairs: the polygons' entries
  bool roomy = false;                 // (the buckets at the cells' rows)
  {
    FaceHand h{faces,
               nse,
               face_ends,
               edges.ids.data(),
               out.source[1].data(),
               face_model,
               face_edge_.data(),
               face_up.offsets,
               face_up_ids,
               face_up.stride,
               cell_count,
               cell_fill_.data(),
               cell_start_.data(),
               C.offsets.data(),
               cell_steps_.data(),
               cell_steps_.size()};
    h.bad = odd_count != 0;
    const bool two = face_up.stride == 2;
    // When the buckets have room for every cell's whole row, each cell's bucket is at its row
    // (no placing, no room to count per face; the cells' step counts, cell_taken_, are zero
    // between slices: reset as each cell is chained). They are given that room when the
    // model's rows are within a small multiple of this slice's (cut face, cell) pairs (a plane
    // meets a good share of a small model's cells), not for large models cut in a small part.
    const std::size_t all_rows = C.ids.size();
    if (buckets && cell_steps_.size() < all_rows &&
        all_rows <= 4 * std::size_t{nse} * (two ? 2 : std::max<std::uint32_t>(face_up.stride, 2))) {
      cell_steps_.resize(all_rows);
      h.bucket = cell_steps_.data();
      h.room = cell_steps_.size();
    }
    roomy = buckets && h.room >= all_rows;
    h.taken = cell_taken_.data();
    for (std::uint32_t se = 0;;) {
      if (!buckets)
        se = two ? hand_faces<false, false, 2>(h, se) : hand_faces<false, false, 0>(h, se);
      else if (roomy)
        se = two ? hand_faces<true, false, 2>(h, se) : hand_faces<true, false, 0>(h, se);
      else
        se = two ? hand_faces<true, true, 2>(h, se) : hand_faces<true, true, 0>(h, se);
      if (se == nse) break;
      // (rare: the buckets keep their storage between slices)
      cell_steps_.resize(std::max(2 * cell_steps_.size(), h.want + 64));
      h.bucket = cell_steps_.data();
      h.room = cell_steps_.size();
    }
    cut_cells_bound = h.pairs;
    if (h.bad) return stop(KernelResult::Generic);
  }
  write_edge_rows(nse, edges.offsets.data(), edges.signs.data());
  // Phase 3, list_marks + tet_polygon / chain_fixed / chain_bucket (rank 3, the facets): a cut cell
  // reads its faces' section edges (one step each, its direction the opposite of the face's sign in
  // the cell); one loop through every step, followed from the smallest tail, is the polygon the
  // generic gathering chains (loops start at the smallest tail, steps follow heads). A pinch, an
  // open chain or several loops: the generic gathering. A tetrahedron's polygon is read from the
  // model's table for the sides of its vertices; another cell of up to 4 faces is chained in
  // registers at a fixed width (no branch on the cut's length), a larger one from the steps its cut
  // faces left in its bucket through a per-section-vertex step map (stamped per cell). All decide
  // alike.
  if (loop_step_.size() < count) loop_step_.resize(count, LoopStep{0, 0, 0});
  Incidence::Storage polys = out.boundary[1].storage();
  constexpr std::uint32_t kSlack = 4;  // (a fixed-width chain writes up to 4 entries)
  polys.ids.resize(cut_cells_bound + kSlack);
  polys.signs.resize(cut_cells_bound + kSlack);
  std::uint32_t npoly = 0;
  {
    if (visit_list_.size() < cut_cells_bound + 8) visit_list_.resize(cut_cells_bound + 8);
    std::uint32_t* const visit = visit_list_.data();
    std::uint32_t* end = visit;
    std::uint64_t odd_mark = 0;  // (every mark is 1)
    for (auto c : touched_)
      end = list_marks(cell_count, m.begin_[2][c], m.begin_[2][c + 1], end, odd_mark);
    const std::uint32_t ncut = static_cast<std::uint32_t>(end - visit);
    polys.offsets.resize(std::size_t{ncut} + 1);
    out.source[2].resize(ncut);
    facet_internal_.resize(ncut);
    const bool above = m.top_ > 3;
    const bool chains_above = above && !m.single_solid_;
    std::uint32_t* const poly_ids = polys.ids.data();
    std::int8_t* const poly_signs = polys.signs.data();
    std::uint32_t* const poly_off = polys.offsets.data();
    poly_off[0] = 0;
    std::uint32_t* const src = out.source[2].data();
    std::uint32_t* const facet = facet_internal_.data();
    LoopStep* const step = loop_step_.data();
    const SliceModel::Compiled::Up solid_up =
        above ? m.up(3) : SliceModel::Compiled::Up{nullptr, nullptr, 0};
    const std::uint32_t* const solid_up_ids = solid_up.ids;
    std::uint64_t* const solid_bits = above ? mark_[4].data() : nullptr;
    const std::uint32_t* const cell_off = C.offsets.data();
    const std::uint32_t* const fill = cell_fill_.data();
    const std::uint32_t* const start = cell_start_.data();
    const CellStep* const bucket = cell_steps_.data();
    const std::uint32_t* const cell_faces = C.ids.data();
    const std::int8_t* const cell_signs = C.signs.data();
    const std::uint32_t* const face_edge = face_edge_.data();
    const std::uint32_t* const edge_row = edges.ids.data();
    const std::uint32_t* const tet_vertex =
        m.tet_vertices_.empty() ? nullptr : m.tet_vertices_.data();
    const std::uint16_t* const tet_case = m.tet_cases_.data();
    std::uint32_t entries = 0;
    bool ok = true;
    // Every polygon from one kind of cell and nothing written above it per polygon: a loop of
    // its own for the kind (tables, or buckets), else the general loop below.
    const bool per_poly_above = above && !m.single_solid_;
    const bool tets_alone = tet_vertex && !per_poly_above;
    const bool buckets_alone = !tet_vertex && !m.small_cells_ && !per_poly_above;
    if (tets_alone) {
      ok = tet_polygons(visit, ncut, tet_vertex, tet_case, side, cell_faces, face_edge, cell_model,
                        poly_ids, poly_signs, poly_off, src, facet, &entries);
      npoly = ok ? ncut : 0;
    } else if (buckets_alone) {
      if (stamp_ > 0xffffffffu - ncut) forget_stamps();  // (the stamps would wrap)
      const auto chain = roomy ? bucket_polygons<true, CellStep, LoopStep>
                               : bucket_polygons<false, CellStep, LoopStep>;
      ok = chain(visit, ncut, bucket, start, fill, cell_off, cell_taken_.data(), step, stamp_ + 1,
                 cell_model, poly_ids, poly_signs, poly_off, src, facet, &entries);
      stamp_ += ncut;
      npoly = ok ? ncut : 0;
    }
    for (const std::uint32_t* it = visit; it != end && ok && !tets_alone && !buckets_alone; ++it) {
      const std::uint32_t x = *it;
      const std::uint32_t b = cell_off[x], nfaces = cell_off[x + 1] - b;
      std::uint32_t added = 0;
      // (every cut cell of a bucket model took steps, small ones too: read below, or not)
      const std::uint32_t taken = roomy ? std::exchange(cell_taken_[x], 0u) : 0u;
      if (tet_vertex) {
        added = tet_polygon(tet_vertex + 4 * x, tet_case + 16 * x, side, cell_faces + b, face_edge,
                            poly_ids + entries, poly_signs + entries);
        ok = added != 7;
      } else if (nfaces <= 4) {
        ok = chain_fixed<4>(cell_faces + b, cell_signs + b, nfaces, face_edge, edge_row,
                            poly_ids + entries, poly_signs + entries, &added);
      } else {
        if (++stamp_ == 0) forget_stamps();  // wrapped
        const std::uint32_t at = roomy ? b : start[x];
        const std::uint32_t ns = roomy ? taken : fill[x] - start[x];
        ok = chain_bucket(bucket + at, ns, step, stamp_, poly_ids + entries, poly_signs + entries,
                          &added);
      }
      if (!ok) break;
      entries += added;
      const std::uint32_t poly = npoly++;
      poly_off[npoly] = entries;
      src[poly] = cell_model ? cell_model[x] : x;
      facet[poly] = x;
      if (above && !m.single_solid_) {
        if (chains_above) {
          images_[3][x] = {gen_, static_cast<std::uint32_t>(terms_[3].size()), 1};
          terms_[3].push_back({poly, 1});
        }
        for (std::uint32_t j = solid_up.begin(x); j < solid_up.end(x); ++j) {  // mark_parents
          const std::uint32_t y = solid_up_ids[j] & kIndex;
          solid_bits[y >> 6] |= std::uint64_t{1} << (y & 63);
        }
      }
    }
    if (!ok) return stop(KernelResult::Generic);
    if (above && m.single_solid_ && npoly > 0) solid_bits[0] |= 1u;  // (every cell's one solid)
    polys.ids.resize(entries);
    polys.signs.resize(entries);
  }
  if (!fixed_chains)
    face_edge_stale_ = true;
  else
    for (const std::uint32_t* it = faces; it != faces_end; ++it) face_edge_[*it] = no_index;
  // (every listed cell made its polygon, npoly == ncut: the polygons' offsets, sources and
  // facets were sized right)
  kernel_count_ += nse + npoly;
  return cut_upper(m, pl, out, 4)
             ? KernelResult::Done
             : KernelResult::General;  // (the rank-4 marks are the generic path's bits)
}

}  // namespace cw4d
