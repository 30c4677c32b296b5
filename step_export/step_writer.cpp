#include "step_writer.h"

#include <limits>
#include <optional>

#include <BRepAlgoAPI_BooleanOperation.hxx>
#include <BRepBndLib.hxx>
#include <Bnd_Box.hxx>
#include <BRepAlgoAPI_Common.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_NurbsConvert.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Controller.hxx>
#include <ShapeUpgrade_UnifySameDomain.hxx>
#include <STEPControl_Reader.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <BRep_Builder.hxx>
#include <gp_Ax2.hxx>
#include <gp_Elips.hxx>
#include <gp_Trsf.hxx>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <vector>

#include "csgfit/error.h"
#include "csgfit/io/files.h"
#include "step_shape.h"
#include "step_solids.h"

namespace csgfit {

namespace {

namespace fs = std::filesystem;
using step::extrude;
using step::finite;
using step::kMaxMagnitude;
using step::local_solid;
using step::polygon_face;
using step::positive;

constexpr double kPi = 3.14159265358979323846;

// OCCT reports failures as Standard_Failure; callers get InputError with a one-line reason.
template <class F>
auto occt(const char* what, F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const Standard_Failure& e) {
    const char* msg = e.GetMessageString();
    throw InputError(std::string("cannot write STEP: ") + what + " failed in OpenCASCADE (" +
                     e.DynamicType()->Name() + (msg && *msg ? std::string(": ") + msg : "") + ")");
  }
}

TopoDS_Shape transformed(const TopoDS_Shape& s, const gp_Trsf& t) {
  // Copy = true bakes the placement into the geometry, so the file carries no locations.
  return BRepBuilderAPI_Transform(s, t, Standard_True).Shape();
}

// model = centre + R * local, R = the quaternion's matrix (its columns are the local axes).
gp_Trsf placement(const Primitive3D& p, const std::string& what) {
  const Quaternion& q = p.rotation;
  for (double v : {q.w, q.x, q.y, q.z}) finite(v, "rotation", what);
  Quaternion u = q;
  u.normalize();
  const Mat3 m = u.matrix();
  gp_Trsf t;
  t.SetValues(m[0][0], m[0][1], m[0][2], finite(p.cx, "centre x", what),  //
              m[1][0], m[1][1], m[1][2], finite(p.cy, "centre y", what),  //
              m[2][0], m[2][1], m[2][2], finite(p.cz, "centre z", what));
  return t;
}

std::string describe(const Primitive3D& p, std::size_t n) {
  return "primitive " + std::to_string(n) + " (" + std::string(to_string(p.kind)) + ")";
}
std::string describe(const Primitive& p, std::size_t n) {
  return "primitive " + std::to_string(n) + " (" + std::string(to_string(p.kind)) + ")";
}

// The 2D primitive as a prism z in [0, t], in model units.
TopoDS_Shape extruded_solid(const Primitive& p, double s, double t, const std::string& what) {
  const double cx = finite(p.cx * s, "centre x", what), cy = finite(p.cy * s, "centre y", what);
  const double w = positive(p.w * s, "width", what), h = positive(p.h * s, "height", what);
  const double a = finite(p.angle, "angle", what) * kPi / 180;
  const double c = std::cos(a), sn = std::sin(a);
  switch (p.kind) {
    case PrimitiveKind::Rectangle: {
      std::vector<gp_Pnt> pts;
      for (auto [u, v] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
        const double x = u * w / 2, y = v * h / 2;
        pts.emplace_back(cx + c * x - sn * y, cy + sn * x + c * y, 0);
      }
      return extrude(polygon_face(pts), t);
    }
    case PrimitiveKind::Circle:
      return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(cx, cy, 0), gp::DZ()), w / 2, t).Shape();
    case PrimitiveKind::Ellipse: {
      if (w == h)
        return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(cx, cy, 0), gp::DZ()), w / 2, t).Shape();
      // gp_Elips wants the major radius along its x direction.
      const bool wide = w > h;
      const gp_Dir major = wide ? gp_Dir(c, sn, 0) : gp_Dir(-sn, c, 0);
      const gp_Elips e(gp_Ax2(gp_Pnt(cx, cy, 0), gp::DZ(), major), std::max(w, h) / 2,
                       std::min(w, h) / 2);
      const TopoDS_Wire wire = BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(e).Edge()).Wire();
      return extrude(BRepBuilderAPI_MakeFace(wire, Standard_True).Face(), t);
    }
    case PrimitiveKind::Triangle: {
      finite(p.apex, "apex", what);
      std::vector<gp_Pnt> pts;
      for (const auto& v : p.triangle_vertices())
        pts.emplace_back(finite(v[0] * s, "corner", what), finite(v[1] * s, "corner", what), 0);
      return extrude(polygon_face(pts), t);
    }
  }
  throw InputError("cannot write STEP: unknown primitive kind");
}

// One n-ary operator over already built children (null shapes are empty sets).
TopoDS_Shape combine(NodeKind kind, std::vector<TopoDS_Shape> kids) {
  if (kind == NodeKind::Union)
    kids.erase(std::remove_if(kids.begin(), kids.end(), [](const TopoDS_Shape& s) { return s.IsNull(); }),
               kids.end());
  if (kids.empty()) return {};
  if (kind == NodeKind::Difference) {
    if (kids.front().IsNull()) return {};
    kids.erase(std::remove_if(kids.begin() + 1, kids.end(), [](const TopoDS_Shape& s) { return s.IsNull(); }),
               kids.end());
  }
  if (kind == NodeKind::Intersection &&
      std::any_of(kids.begin(), kids.end(), [](const TopoDS_Shape& s) { return s.IsNull(); }))
    return {};
  if (kids.size() == 1) return kids.front();

  const char* name = kind == NodeKind::Union ? "union" : kind == NodeKind::Difference ? "difference" : "intersection";
  // Union and difference are one General Fuse run over all children (first child the object,
  // the rest tools); intersection is a chain of pairwise commons (an n-ary common of the
  // arguments is not what BRepAlgoAPI_Common computes with several tools).
  // OpenCASCADE can return a valid-looking solid of the wrong volume (measured: a cylinder
  // minus a B-spline ellipsoid came out 12 % larger than the cylinder). Every result is held to
  // the bounds its operands' volumes allow; a result outside them is built again with a fuzzy
  // tolerance, and if that fails too the STEP is refused rather than written wrong.
  auto volume_ok = [&](const TopTools_ListOfShape& args, const TopTools_ListOfShape& tools,
                       const TopoDS_Shape& result) {
    std::vector<double> va, vt;
    for (const TopoDS_Shape& a : args) va.push_back(std::fabs(shape_volume(a)));
    for (const TopoDS_Shape& t : tools) vt.push_back(std::fabs(shape_volume(t)));
    double sum = 0, biggest = 0, smallest = std::numeric_limits<double>::infinity();
    for (double v : va) sum += v, biggest = std::max(biggest, v), smallest = std::min(smallest, v);
    for (double v : vt) sum += v, biggest = std::max(biggest, v), smallest = std::min(smallest, v);
    const double v = result.IsNull() ? 0.0 : shape_volume(result);
    const double tol = 1e-6 * sum + 1e-12;
    if (!(v >= -tol)) return false;
    if (kind == NodeKind::Union) return v >= biggest - tol && v <= sum + tol;
    if (kind == NodeKind::Intersection) return v <= smallest + tol;
    const double base = va.front();
    double cut = 0;
    for (double t : vt) cut += t;
    return v <= base + tol && v >= base - cut - tol;
  };
  auto run = [&](BRepAlgoAPI_BooleanOperation& op, const TopTools_ListOfShape& args,
                 const TopTools_ListOfShape& tools) {
    for (int attempt = 0; attempt < 2; ++attempt) {
      op.SetArguments(args);
      op.SetTools(tools);
      op.SetRunParallel(Standard_False);  // the machine is shared; trees are small
      if (attempt == 1) {
        Bnd_Box box;
        for (const TopoDS_Shape& a : args) BRepBndLib::Add(a, box);
        op.SetFuzzyValue(1e-7 * std::sqrt(box.SquareExtent()));
      }
      op.Build();
      if (!op.IsDone() || op.HasErrors()) continue;
      const TopoDS_Shape result = op.Shape();
      if (volume_ok(args, tools, result)) return std::optional<TopoDS_Shape>(result);
    }
    return std::optional<TopoDS_Shape>();
  };
  const auto refuse = [&] {
    return InputError(std::string("cannot write STEP: OpenCASCADE's ") + name +
                      " gave a solid of impossible volume (write .scad or .json instead)");
  };
  // One operand at a time: each step checked on its own. The n-ary run comes first (one
  // General Fuse is faster and exact where it works); blocks that share faces, such as the
  // extrusions of a scan's height levels all standing on one floor, can defeat it.
  const auto pairwise = [&](auto make_op) {
    TopoDS_Shape acc = kids.front();
    for (std::size_t i = 1; i < kids.size(); ++i) {
      TopTools_ListOfShape a, b;
      a.Append(acc);
      b.Append(kids[i]);
      auto op = make_op();
      const std::optional<TopoDS_Shape> r = run(op, a, b);
      if (!r) throw refuse();
      acc = *r;
    }
    return acc;
  };
  if (kind == NodeKind::Intersection) return pairwise([] { return BRepAlgoAPI_Common(); });
  TopTools_ListOfShape args, tools;
  args.Append(kids.front());
  for (std::size_t i = 1; i < kids.size(); ++i) tools.Append(kids[i]);
  std::optional<TopoDS_Shape> all;
  if (kind == NodeKind::Union) {
    BRepAlgoAPI_Fuse op;
    all = run(op, args, tools);
  } else {
    BRepAlgoAPI_Cut op;
    all = run(op, args, tools);
  }
  if (all) return *all;
  if (kids.size() < 3) throw refuse();
  if (kind == NodeKind::Union) return pairwise([] { return BRepAlgoAPI_Fuse(); });
  return pairwise([] { return BRepAlgoAPI_Cut(); });
}

template <class N, class Leaf>
TopoDS_Shape build(const N& n, std::size_t& count, const Leaf& leaf) {
  if (n.is_leaf()) return leaf(n.primitive, ++count);
  std::vector<TopoDS_Shape> kids;
  kids.reserve(n.children.size());
  for (const N& c : n.children) kids.push_back(build(c, count, leaf));
  return combine(n.kind, std::move(kids));
}

// The result as one solid where it is one, checked.
TopoDS_Shape finish(const TopoDS_Shape& shape) {
  std::vector<TopoDS_Shape> solids;
  if (!shape.IsNull())
    for (TopExp_Explorer ex(shape, TopAbs_SOLID); ex.More(); ex.Next()) solids.push_back(ex.Current());
  if (solids.empty()) throw InputError("cannot write STEP: the tree's solid is empty");
  // Booleans of fitted primitives leave slivers where two faces nearly meet (measured on
  // InverseCSG 011: a 0.008 x 0.04 x 0.009 piece, 2e-7 of the part's volume, floating beside
  // it). A CAD user would see a second body; one below 1e-6 of the volume is dropped.
  if (solids.size() > 1) {
    std::vector<double> volumes;
    double total = 0;
    for (const TopoDS_Shape& s : solids) total += volumes.emplace_back(shape_volume(s));
    std::vector<TopoDS_Shape> kept;
    for (std::size_t i = 0; i < solids.size(); ++i)
      if (volumes[i] >= 1e-6 * total) kept.push_back(solids[i]);
    if (!kept.empty()) solids = std::move(kept);
  }
  TopoDS_Shape out;
  if (solids.size() == 1) {
    out = solids.front();
  } else {
    // Disjoint pieces (a union of parts that do not touch) stay separate solids.
    TopoDS_Compound c;
    BRep_Builder b;
    b.MakeCompound(c);
    for (const TopoDS_Shape& s : solids) b.Add(c, s);
    out = c;
  }
  if (!BRepCheck_Analyzer(out).IsValid())
    throw InputError("cannot write STEP: OpenCASCADE built an invalid solid for this tree");
  const double volume = shape_volume(out);
  if (!(volume > 0)) throw InputError("cannot write STEP: the tree's solid is empty");
  // Merges the faces the booleans split that lie on one surface (coplanar box faces, the tops
  // of extruded 2D shapes), so the file has the faces a CAD user expects. Best effort: it
  // throws on some B-spline (ellipsoid) edges, and then the unmerged solid is written.
  try {
    ShapeUpgrade_UnifySameDomain unify(out, Standard_True, Standard_True, Standard_False);
    unify.Build();
    const TopoDS_Shape merged = unify.Shape();
    if (!merged.IsNull() && BRepCheck_Analyzer(merged).IsValid() &&
        std::fabs(shape_volume(merged) - volume) <= 1e-9 * volume)
      return merged;
  } catch (const Standard_Failure&) {
  }
  return out;
}

std::string lower_extension(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& ch : ext) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  return ext;
}

// The part's name in CAD trees: the input's stem ("bracket" for bracket.png).
std::string product_name(const std::string& source) {
  const std::string stem = fs::path(source).stem().string();
  return stem.empty() ? "csgfit" : stem;
}

}  // namespace

TopoDS_Shape make_shape(const Primitive3D& p) {
  const std::string what = describe(p, 1);
  return occt("building a primitive", [&] { return transformed(local_solid(p, what), placement(p, what)); });
}

TopoDS_Shape make_shape(const Node3D& tree) {
  return occt("building the solid", [&] {
    std::size_t count = 0;
    const TopoDS_Shape raw = build(tree, count, [](const Primitive3D& p, std::size_t n) {
      const std::string what = describe(p, n);
      return transformed(local_solid(p, what), placement(p, what));
    });
    return finish(raw);
  });
}

TopoDS_Shape make_shape(const Node& tree, const ModelFrame& frame) {
  if (!std::isfinite(frame.thickness) || frame.thickness < 0 || frame.thickness > kMaxMagnitude)
    throw InputError("cannot write STEP: thickness must be a finite number >= 0");
  if (frame.thickness == 0)
    throw InputError("cannot write STEP: STEP needs a thickness (this 2D result is flat; fit it "
                     "with --thickness)");
  if (!std::isfinite(frame.pixel_size) || !(frame.pixel_size > 0) || frame.pixel_size > kMaxMagnitude)
    throw InputError("cannot write STEP: pixel size must be a positive finite number");
  return occt("building the solid", [&] {
    std::size_t count = 0;
    const TopoDS_Shape raw = build(tree, count, [&](const Primitive& p, std::size_t n) {
      return extruded_solid(p, frame.pixel_size, frame.thickness, describe(p, n));
    });
    return finish(raw);
  });
}

double shape_volume(const TopoDS_Shape& shape) {
  return occt("the volume", [&] {
    GProp_GProps props;
    // The adaptive integration with a relative error bound: the default Gauss rule's error on
    // a B-spline ellipsoid is not bounded.
    BRepGProp::VolumeProperties(shape, props, 1e-9, Standard_True);
    return props.Mass();
  });
}

void write_step_shape(const TopoDS_Shape& shape, const std::string& path,
                      const std::string& name) {
  std::error_code ec;
  if (fs::is_directory(fs::path(path), ec)) throw InputError("cannot write '" + path + "': it is a folder");
  const std::string tmp = make_temp_beside(path);  // OCCT writes by file name
  try {
    occt("writing STEP", [&] {
      // The writer's settings are process-wide statics; one write at a time.
      static std::mutex mutex;
      std::lock_guard<std::mutex> lock(mutex);
      STEPControl_Controller::Init();
      // OCCT reports each transfer on stdout; the CLI's stdout is not OCCT's to use.
      static std::once_flag quiet;
      std::call_once(quiet, [] {
        Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
      });
      Interface_Static::SetCVal("write.step.schema", "AP214IS");
      Interface_Static::SetCVal("write.step.unit", "MM");
      Interface_Static::SetCVal("xstep.cascade.unit", "MM");
      Interface_Static::SetCVal("write.step.product.name", name.c_str());
      // The file is read back and its volume compared with the solid's: a boolean face on a
      // transformed (B-spline) sphere can come back from STEP with its trimming lost (measured:
      // a cylinder minus an ellipsoid read back 50 % too large). Then the solid is written
      // again as NURBS throughout, and if that does not read back right either, refused.
      const double expected = shape_volume(shape);
      for (int attempt = 0; attempt < 2; ++attempt) {
        TopoDS_Shape out = shape;
        if (attempt == 1) out = BRepBuilderAPI_NurbsConvert(shape, Standard_True).Shape();
        STEPControl_Writer writer;
        if (writer.Transfer(out, STEPControl_AsIs) != IFSelect_RetDone)
          throw InputError("cannot write '" + path + "': OpenCASCADE could not translate the solid");
        if (writer.Write(tmp.c_str()) != IFSelect_RetDone)
          throw InputError("cannot write '" + path + "': OpenCASCADE could not write the file");
        STEPControl_Reader reader;
        if (reader.ReadFile(tmp.c_str()) != IFSelect_RetDone) continue;
        reader.TransferRoots();
        const TopoDS_Shape back = reader.OneShape();
        if (back.IsNull()) continue;
        const double got = shape_volume(back);
        if (std::fabs(got - expected) <= 1e-6 * std::fabs(expected) + 1e-12) return 0;
      }
      throw InputError("cannot write '" + path + "': the STEP file does not read back as the "
                       "solid written (an OpenCASCADE limitation; write .scad or .json instead)");
    });
    publish_file(tmp, path);
  } catch (...) {
    std::remove(tmp.c_str());
    throw;
  }
}

void write_step(const Node3D& tree, const std::string& path, const StepOptions& options) {
  write_step_shape(make_shape(tree), path, product_name(options.source));
}

void write_step(const Node& tree, const ModelFrame& frame, const std::string& path,
                const StepOptions& options) {
  write_step_shape(make_shape(tree, frame), path,
                   product_name(options.source.empty() ? frame.source : options.source));
}

double step_volume(const Node3D& tree) { return shape_volume(make_shape(tree)); }
double step_volume(const Node& tree, const ModelFrame& frame) {
  return shape_volume(make_shape(tree, frame));
}

bool is_step_path(const std::string& path) {
  const std::string ext = lower_extension(path);
  return ext == ".step" || ext == ".stp";
}

}  // namespace csgfit
