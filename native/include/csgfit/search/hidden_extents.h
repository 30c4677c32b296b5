// Hidden faces where the designer would have put them: a block's face that no view saw is
// moved out to a plane the part already has (another block's face, a cylinder's or sphere's
// tangent plane) or to the block's own width, as a CAD user aligns an unseen underside with
// the features beside it or draws a cube; a hole's or a pocket's unseen end goes through.
#pragma once

#include "csgfit/features/range_evidence.h"
#include "csgfit/seed/precedence_graph.h"

namespace csgfit {

/// `graph` with each positive block's faces where a designer would have put them: each face
/// first moves in to seed 002's smallest hidden extent (as far as the views see no
/// difference), then out to a plane parallel to it that another positive, unconjectured node
/// bounds (up to half the block's size past where the face was) or to where the block is as
/// deep as one of its other sizes that a view or such a move put (growing by at most its depth
/// as found: a cube, not a plate made a cube; or coming in by less than the tolerance); the
/// plane that most of the part's planes agree with (within the evidence's tolerance) first,
/// then the one they agree with more closely, then the nearest; each when the views do not see
/// the difference (no surface, empty or behind point of `evidence` agrees less; one sample less
/// for a face that turns its back on every view, where sensor noise is all there is, half of
/// one for any other). A face with no such plane stays where it was. A block's faces are
/// aligned again while a pass moves one. Each positive cylinder's end no view sees moves out,
/// within the
/// cylinder's length, to the nearest face of a block its axis then meets (a table's leg up to
/// the top it carries). Nothing moves when the evidence has no hidden points (a scan without a
/// camera). Deterministic.
PrecedenceGraph align_hidden_faces(PrecedenceGraph graph, const RangeEvidence& evidence);

/// `graph` with each hole (a negative, unconjectured cylinder) and each pocket (a negative
/// block, conjectured or not) through what it cuts: an end or a face no view sees moved past the
/// far side of the positive nodes it is subtracted from, as a machinist drills or mills through
/// unless the bottom is seen; kept when the views do not see the difference (no surface, empty
/// or behind point of `evidence` agrees less). Nothing moves when the evidence has no hidden
/// points. Deterministic.
PrecedenceGraph holes_through(PrecedenceGraph graph, const RangeEvidence& evidence);

/// `graph` with each block cut (conjectured too) clear of the skins it leaves: a face that ends
/// within the evidence's tolerance of a parallel face of a positive it is subtracted from (a
/// cut drawn to a block's face and read a hair short) moved a tolerance past it, when the views
/// see a difference within a quarter of the size weight `k`. A skin is thinner than the views
/// can tell, yet OpenSCAD and OCCT render it and a sensor sees it as silhouette. Deterministic.
PrecedenceGraph clear_skins(PrecedenceGraph graph, const RangeEvidence& evidence, double k);

/// `graph` with each halfspace cut (SignedPrimitive::halfspace) that trims only blocks, each
/// through a whole face parallel to its plane, taken into those blocks: their faces moved to the
/// plane and the cut dropped, when the views do not see the difference (within a quarter of the
/// size weight `k`). A block's own face is then what the views hold, where under a cut through
/// its plane the block could drift unseen. Deterministic.
PrecedenceGraph faces_from_cuts(PrecedenceGraph graph, const RangeEvidence& evidence, double k);

}  // namespace csgfit
