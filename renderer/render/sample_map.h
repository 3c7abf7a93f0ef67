// Adaptive sampling: how many samples each pixel takes in a pass. The first passes (the pilot)
// sample every pixel alike; every later pass gives pixel i a number of samples proportional to its
// per-sample standard deviation measured by the pilot, which minimizes the image's summed variance
// (the reported error) for the same total: minimize sum(sigma_i^2 / n_i) subject to sum(n_i) = N
// gives n_i proportional to sigma_i (a Lagrange multiplier; Mitchell 1987 and Hachisuka et al.
// 2008 allocate by the same kind of estimate).
//
// The map depends on the pilot passes alone, so every pass is still a function of (scene, settings,
// pass): split renders stay bit-identical (a range that starts after the pilot renders the pilot
// for itself), and passes stay independent given the map, so the pass variance stays a valid
// error estimate: pass means are unbiased however many samples they take, and with equal weights
// the sample variance of the pass means over n is an unbiased estimate of the variance of their
// mean even when the passes' variances differ.
#pragma once

#include <cstdint>
#include <vector>

#include "film/film.h"

namespace caustic {

/// Passes of the pilot: 8 estimates of each pixel's variance (7 degrees of freedom).
constexpr int kAdaptivePilotPasses = 8;

/// Samples per pixel for each pass after the pilot, from `pilot` (a film of exactly the pilot's
/// passes, rendered with `sppPerPass` samples per pixel): about sppPerPass on average, at least
/// max(1, sppPerPass / 4) and at most 8 sppPerPass per pixel, in proportion to the standard
/// deviation of the pixel's samples (over its channels), blurred over 3 x 3 pixels so that a
/// pixel whose few pilot samples missed a rare bright path still gets its neighbours' share.
/// Deterministic: the same film gives the same map on any machine.
std::vector<uint16_t> adaptiveSampleMap(const Film& pilot, int sppPerPass);

}  // namespace caustic
