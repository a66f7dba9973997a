// The example scenes of `untangle simulate --example` (paper §IV): the app runs them, the tests run
// coarser versions of the same scenes.
#pragma once

#include <string>

#include "untangle/simulate.h"

namespace untangle::scenes {

// Folder of the MakeHuman garment and body shipped in testdata/makehuman (CC0).
std::string makehuman_dir();

// The names --example takes, for messages: "ball, box, spikes, cow or fitting".
const char* simulation_example_names();

// The example scene `name`; `resolution` is the vertices per side of each sheet (0: the paper's
// 81, 6,561 particles a sheet; the tests pass fewer). Metres and y up, except fitting (the
// MakeHuman frame: decimetres, y up).
//   ball:    a sheet 0.2 above a ball of radius 0.5;
//   box:     the same sheet over a closed box;
//   spikes:  a sheet 2 a side dropped on 4 x 4 cone spikes 0.4 tall (tips are vertices);
//   cow:     four sheets 1.1 a side dropped one above the other onto the cow of libcgal-demo;
//   fitting: the MakeHuman casual suit on its body (the garment penetrating it as shipped), the
//            body growing back from 0.97 of its size to 1 over 20 frames; without gravity.
// Throws Error(kUsage) for an unknown name, Error(kUnreadableInput) when a mesh the scene needs
// (the cow, the garment) is not installed.
SimulationScene simulation_example(const std::string& name, int resolution = 0);

}  // namespace untangle::scenes
