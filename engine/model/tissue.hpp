// The initial tissue of a scene: the epidermal-sheet generator or an HDF5 state (`tissue.file`, read by the reader
// it is given: io/io.hpp make_tissue gives read_state), and the boxes around a tissue.
#pragma once
#include <functional>
#include <string>

#include "scene.hpp"
#include "state.hpp"

namespace semlb::engine {

// Builds the tissue (`tissue.file`, relative to the scene, read by `read_file`) and, for `domain: auto`, sets the
// scene's box around it. Throws InputError.
State make_tissue(Scene& scene, const std::function<State(const std::string& path)>& read_file);
// The scene's tissue section read and checked as make_tissue reads it (the file or the generator's keys, x_range),
// without building the tissue or reading the file (InputError naming the key's file and line or flag).
void check_tissue(const Scene& scene);
// The elements' bounding box over finite coordinates ({lo, hi} in um; zeros when there are none), as Backend::bounds().
std::pair<std::array<double, 3>, std::array<double, 3>> element_bounds(const State& state);
// The box `domain: auto` gives a tissue: its extent plus one cutoff, from z = -cutoff, with headroom above.
std::pair<std::array<double, 3>, std::array<double, 3>> tissue_box(const State& state, double cutoff);
// The same box from an extent (lo, hi per axis, um) measured elsewhere (Backend::bounds()).
std::pair<std::array<double, 3>, std::array<double, 3>> padded_box(std::array<double, 3> lo, std::array<double, 3> hi,
                                                                   double cutoff);
void fit_box(Scene& scene, const State& state);

}  // namespace semlb::engine
