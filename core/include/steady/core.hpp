#pragma once
/// @file
/// Everything of steady::core: affinities and the EAR (logarithms, powers, SAM spans).
#include <steady/core/affine.hpp>
#include <steady/core/ear.hpp>
#include <steady/core/error.hpp>
