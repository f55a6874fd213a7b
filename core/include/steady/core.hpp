#pragma once
/// @file
/// Everything of steady::core: affinities, the EAR (logarithms, powers, SAM spans) and motions
/// (polySAMs, Bézier and bi-arc motions, subdivision, patches, steadiness measure).
#include <steady/core/affine.hpp>
#include <steady/core/ear.hpp>
#include <steady/core/error.hpp>
#include <steady/core/motion.hpp>
