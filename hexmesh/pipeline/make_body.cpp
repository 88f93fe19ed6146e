#include "hexmesh/pipeline/make_body.h"

#include <fmt/format.h>

#include <memory>
#include <ostream>

#include "io/sample_readers.h"
#include "io/surface_reader.h"
#include "surface/analytic.h"
#include "surface/cross_sections.h"
#include "surface/csg.h"
#include "surface/mesh_sdf.h"
#include "surface/point_cloud.h"
#include "surface/surface_diagnostics.h"
#include "surface/transform.h"

namespace hexmesh {

TriangleSurface read_surface_file(const std::string& file, std::string* note) {
    SurfaceReadOptions loose;
    loose.allow_degenerate = true;
    long long removed = 0;
    if (std::optional<TriangleSurface> s =
            without_zero_area_triangles(read_surface(file, loose), removed)) {
        if (note && removed > 0)
            *note = fmt::format(
                "{} zero-area triangle{} of the surface removed (flipped, collapsed or dropped)",
                removed, removed > 1 ? "s" : "");
        return std::move(*s);
    }
    try {
        read_surface(file);  // throws, naming the first zero-area triangle
    } catch (const InputError& e) {
        throw InputError(std::string(e.what()) +
                         "; it cannot be flipped or collapsed away (the triangles around it do "
                         "not make a closed, consistently oriented surface, or it is only nearly "
                         "flat)");
    }
    throw InputError(file + ": its zero-area triangles cannot be flipped or collapsed away");
}

namespace {

Body make_shape(const GeometrySpec& s) {
    if (s.kind == BodyKind::sphere) return std::make_shared<Sphere>(s.center, s.radius);
    if (s.kind == BodyKind::ellipsoid) return std::make_shared<Ellipsoid>(s.center, s.semi_axes);
    if (s.kind == BodyKind::box) return std::make_shared<Box>(s.center, 0.5 * s.size);
    if (s.kind == BodyKind::cylinder)
        return std::make_shared<Cylinder>(s.center, s.radius, 0.5 * s.height);
    if (s.kind == BodyKind::torus)
        return std::make_shared<Torus>(s.center, s.major_radius, s.minor_radius);
    if (s.kind == BodyKind::cone)
        return std::make_shared<Cone>(s.center, s.bottom_radius, s.top_radius, 0.5 * s.height);
    if (s.kind == BodyKind::file) {
        MeshSdfOptions options;
        options.voxel_size = s.voxel_size;
        options.feature_angle = s.feature_angle;
        const TriangleSurface surface = read_surface_file(s.file);
        return naming_file(s.file, [&] { return std::make_shared<MeshSdf>(surface, options); });
    }
    if (s.kind == BodyKind::points)
        return std::make_shared<PointCloudSdf>(read_point_cloud(s.file));
    if (s.kind == BodyKind::sections)
        return std::make_shared<CrossSectionSdf>(read_sections(s.file));
    std::vector<Body> children;
    for (const GeometrySpec& c : s.children) children.push_back(make_body(c));
    const CsgOp op = s.kind == BodyKind::csg_union          ? CsgOp::Union
                     : s.kind == BodyKind::csg_intersection ? CsgOp::Intersection
                                                            : CsgOp::Difference;
    return std::make_shared<Csg>(op, std::move(children));
}

}  // namespace

std::optional<TriangleSurface> reference_surface(const GeometrySpec& spec, std::ostream* log) {
    if (spec.kind != BodyKind::file) return std::nullopt;
    std::string note;
    TriangleSurface surface = read_surface_file(spec.file, &note);
    if (!note.empty() && log) *log << "  " << note << "\n";
    const Mat3 rotation = rotation_from_axis_angle(spec.rotate_axis, spec.rotate_degrees);
    for (Vec3& p : surface.points) p = spec.translate + spec.scale * (rotation * p);
    // Triangles that all face inwards (some writers' convention, e.g. marching cubes on a
    // distance field) would map the surface onto the sphere mirrored, and the wall grid built
    // through that map inside out: they are turned over.
    if (signed_volume(surface) < 0) turn_over(surface);
    return surface;
}

Body make_body(const GeometrySpec& spec) {
    Body body = make_shape(spec);
    const bool moved = spec.translate.norm() > 0 || spec.rotate_degrees != 0 || spec.scale != 1;
    if (!moved) return body;
    return std::make_shared<Transformed>(
        body, spec.translate, rotation_from_axis_angle(spec.rotate_axis, spec.rotate_degrees),
        spec.scale);
}

}  // namespace hexmesh
