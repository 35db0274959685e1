#pragma once
// A small valid scenario for tests, with known line numbers.

#include <string>

namespace hcpf::scenarios::testing {

// Line numbers (1-based) are relied on by bad-input tests: keep in step.
inline const char* kMinimal =
    "name: minimal\n"                                                             // 1
    "seed: 7\n"                                                                   // 2
    "frames: 20\n"                                                                // 3
    "camera:\n"                                                                   // 4
    "  resolution: [320, 240]\n"                                                  // 5
    "  fov_deg: 40\n"                                                             // 6
    "  path:\n"                                                                   // 7
    "    - {frame: 0, position: [0, -20, 120], look_at: [0, 0, 0]}\n"             // 8
    "targets:\n"                                                                  // 9
    "  - id: 1\n"                                                                 // 10
    "    dimensions_m: [4.5, 2.0, 1.6]\n"                                         // 11
    "    path: {waypoints: [[-20, 0], [20, 0]], speed_mps: 6}\n"                  // 12
    "  - id: 2\n"                                                                 // 13
    "    dimensions_m: [5, 2.2, 2]\n"                                             // 14
    "    path: {waypoints: [[0, -20], [0, 20]], speed_mps: 6, start_frame: 2}\n"  // 15
    "tracker:\n"                                                                  // 16
    "  particles: 100\n"                                                          // 17
    "  resampling: {method: charged, beta: 2.0}\n";                               // 18

}  // namespace hcpf::scenarios::testing
