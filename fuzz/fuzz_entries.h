// The per-input logic of the fuzz targets, shared by the libFuzzer entry points (fuzz/fuzz_*.cpp,
// clang only) and the corpus replay test (tests/test_fuzz_corpus.cpp, any compiler), so that the
// seed corpora run through exactly the fuzzed code in every CI build.
//
// Both functions return 0 for every input (libFuzzer's convention). Bad input that the library
// rejects with untangle::Error is an allowed outcome; a violated invariant prints one line to
// stderr and aborts, so libFuzzer records the input and a test run fails loudly. Any other
// exception escapes (libFuzzer reports it as a crash).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "contour/build_contours.h"
#include "detect/detect_crossings.h"
#include "topology/scene_topology.h"

namespace untangle::fuzz {

// The loader: the first byte picks the file extension (see extension_for in fuzz_entries.cpp:
// 'o' obj, 'f' off, 'p' ply, 's' stl, 'g' gltf, 'b' glb, 'x' fbx, ...; other bytes map onto the
// same list), the rest is the file's content. A file that loads then goes through
// find_intersections, whose result must hold no broken contour.
int fuzz_load_one(const std::uint8_t* data, std::size_t size);

// Contour building: the bytes describe a small scene of sheets, triangle soups and tetrahedra on
// a coarse integer grid (so vertices on faces, edges through edges and coplanar pairs are
// common). Detection is checked against a brute-force test of every edge against every face and
// against the 0-or-2 property, build_contours against its invariants; then the rest of the bytes
// choose a raw crossing set (a subset of the real crossings and invented ones, ids in range) that
// build_contours must also survive.
int fuzz_contours_one(const std::uint8_t* data, std::size_t size);

// A crossing set as CrossingSet requires it: sorted by (edge, face), unique (the first of equal
// pairs is kept).
CrossingSet make_crossing_set(std::vector<RawCrossing> items);

// The invariants build_contours keeps for any crossing set whose ids are in range (sorted, unique:
// the CrossingSet contract): contours index into the set, every crossing lies on exactly one
// contour, and the bookkeeping is consistent. With `from_detection` (the set is a real detection)
// additionally: no contour is broken. Aborts with a message on violation.
void check_contours(const SceneTopology& topology, const CrossingSet& set,
                    const std::vector<TracedContour>& contours, bool from_detection);

}  // namespace untangle::fuzz
