// What the renderer's passes share (renderer.cpp runs them in order): the
// sizes of the opacity maps and the strand texture, and the pass clock.
#pragma once

#include <chrono>

namespace loosehair::render {

inline constexpr int kSlices = 16;
inline constexpr int kSliceLayers = 5;                        // RGBA layers holding slices 3l .. 3l+3
inline constexpr int kStrandWidth = 32, kStrandHeight = 128;  // the strand texture, texels
inline constexpr int kStrandLevels = 5;  // its mip levels down to 1 texel across: log2(kStrandWidth)
inline constexpr int kShadowSize = 256;  // opacity varies smoothly; 256^2 keeps the light pass cheap

using PassClock = std::chrono::steady_clock;
inline double since(PassClock::time_point t) { return std::chrono::duration<double>(PassClock::now() - t).count(); }

}  // namespace loosehair::render
