// Internal to construct/: the construction's tuning constants, in one place, each with why.
#pragma once

#include <limits>

namespace csgfit::construct {

/// A cylinder whose faces go this far about its axis (degrees) is whole: no plane through its
/// axis separates anything of it (a hole or a boss); less, and it is an arc beside a block.
constexpr double kWholeSweep = 330;
/// Arcs that may be a rounded outline's corners: from this sweep (degrees; a quarter is 90)...
constexpr double kLeastCornerSweep = 60;
/// ...and past this one a slot's half circle.
constexpr double kHalfSweep = 150;
/// An arc is the corner its place in the outline asks for when its middle faces within about
/// 25 degrees of that corner's outward direction (this cosine).
constexpr double kCornerFacing = 0.9;
/// Price of a plane term in a product, in primitives: five planes make a box.
constexpr double kPlaneCost = 0.2;
/// A separating plane (through an axis, a centre) makes a part of a primitive: dearer.
constexpr double kSeparatingPlaneCost = 0.5;
/// Most terms a product grows to (a box is 6, a cylinder with caps 3; a slot's end a few more).
constexpr int kMostTerms = 24;
/// A product may keep forbidden samples no term separates up to this share of the samples it
/// holds (the file's rounding on a face between two cells); more, and it is no candidate.
constexpr double kUnseparatedShare = 0.002;
/// Most candidates grown per kind, and most growths tried (a cell no product can hold costs a
/// growth too), so that a part of thousands of cells stays quick.
constexpr std::size_t kMostCandidates = 400;
constexpr std::size_t kMostGrowths = 800;
/// And most words of samples counted per kind (the bound a literal's count is charged; about
/// half a minute of counting on one core, more than a 600-literal CAD part asks for): a budget
/// that, unlike the clock, gives the same tree on every machine.
constexpr std::size_t kMostWordsCounted = 8000000000;
/// The price of a term to a growth, as a share of the solid's weight: small, since keeping
/// samples matters more than a short product; a curved term costs five planes' worth.
constexpr double kLiteralPrice = 0.002;
/// A hole counts as cut into the part (positives may fill it) when this share of its empty
/// samples lies between solid along some axis.
constexpr double kEnclosedShare = 0.5;
/// The set cover also starts from each of this many largest candidates (its greedy is myopic).
constexpr std::size_t kCoverStarts = 16;

}  // namespace csgfit::construct
