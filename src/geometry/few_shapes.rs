//! Rays in lanes against a few simple shapes (planes, spheres, planar shapes): each shape's
//! test runs on the rays' coordinates side by side in SIMD lanes. With paths traced `LANES`
//! at a time, a scene of a few shapes costs a fraction of a test per ray and shape, less than
//! traversing a hierarchy over them; the unbounded planes have no hierarchy to live in at all.
//!
//! Each kind's test is its one-ray test's kernel (`plane_distance`, `sphere_distance`,
//! `planar_distance` and their points) run on lanes, so a shape has the same intersections
//! here as there. (`scene::build` picks them for
//! a scene whose bounded shapes are few and simple; planes are always here.)

use super::planar::{Planar, PlanarKind, planar_distance, planar_error, planar_point};
use super::shape::{
    Shape, plane_distance, plane_point, sphere_distance, sphere_error, sphere_point,
};
use crate::lanes::{Floats, HitLanes, LANES, Lane, Mask, MaskLanes, RayLanes, Real, Vec3Lanes};
use crate::ray::Hit;

/// A simple shape with its parameters splatted over the lanes once, at build time.
// Kept inline, though a planar shape is the largest: the tests read the few shapes in order,
// and a box around each would add a load to every test.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
enum Simple {
    Plane {
        normal: Vec3Lanes,
        offset: Floats,
    },
    Sphere {
        center: Vec3Lanes,
        radius: Floats,
        error: Floats,
    },
    Planar {
        kind: PlanarKind,
        hole: Floats,
        origin: Vec3Lanes,
        edge1: Vec3Lanes,
        edge2: Vec3Lanes,
        normal: Vec3Lanes,
        error: Floats,
    },
}

/// The nearest shape met in each lane: its name (`None` for none), and there the distance
/// and the hit record.
#[derive(Debug, Clone, Copy)]
pub struct Nearest {
    pub names: [Option<u32>; LANES],
    pub t: Floats,
    pub hits: HitLanes,
}

impl Nearest {
    /// The hit record of each lane whose ray met a shape, named as its primitive. All lanes are
    /// read at once, each at a lane known when compiling: read one lane at a time by a variable
    /// lane, LLVM gathered a lane's ten coordinates (`vgatherqps`), which cannot take them from
    /// the stores that had just made them and waited for those (the hottest instruction of S3's
    /// `radiance_of_all` in `perf annotate`).
    #[inline]
    pub fn hits(&self) -> [Option<Hit>; LANES] {
        std::array::from_fn(|lane| Some(self.hits.lane(lane, self.names[lane]?, self.t.lane(lane))))
    }
}

#[derive(Debug, Clone, Default)]
pub struct FewShapes {
    shapes: Vec<Simple>,
    /// The name each shape was given (its primitive's index).
    names: Vec<u32>,
}

impl FewShapes {
    /// Whether `new` takes this kind of shape.
    pub fn takes(shape: &Shape) -> bool {
        matches!(
            shape,
            Shape::Plane { .. } | Shape::Sphere { .. } | Shape::Planar { .. } | Shape::Box(_)
        )
    }

    /// How many simple shapes a shape `takes` accepts is tested as (a box as its six faces).
    pub fn size(shape: &Shape) -> usize {
        if matches!(shape, Shape::Box(_)) { 6 } else { 1 }
    }

    /// Shapes that `takes` accepts, each with the name results give it. A box is tested as its
    /// six faces, each named as the box (their hit records are the box's).
    pub fn new<'a>(shapes: impl IntoIterator<Item = (u32, &'a Shape)>) -> Self {
        let faces: Vec<(u32, Shape)> = shapes
            .into_iter()
            .flat_map(|(name, shape)| match shape {
                Shape::Box(cuboid) => {
                    cuboid.faces.iter().map(|&face| (name, Shape::Planar(face))).collect::<Vec<_>>()
                }
                shape => vec![(name, shape.clone())],
            })
            .collect();
        let (names, shapes): (Vec<u32>, Vec<Shape>) = faces.into_iter().unzip();
        let shapes = shapes
            .iter()
            .map(|shape| match *shape {
                Shape::Plane { normal, offset } => Simple::Plane {
                    normal: Vec3Lanes::splat(normal),
                    offset: Floats::splat(offset),
                },
                Shape::Sphere { center, radius } => Simple::Sphere {
                    center: Vec3Lanes::splat(center),
                    radius: Floats::splat(radius),
                    error: Floats::splat(sphere_error(center, radius)),
                },
                Shape::Planar(Planar { kind, origin, edge1, edge2, normal, hole }) => {
                    Simple::Planar {
                        kind,
                        hole: Floats::splat(hole),
                        origin: Vec3Lanes::splat(origin),
                        edge1: Vec3Lanes::splat(edge1),
                        edge2: Vec3Lanes::splat(edge2),
                        normal: Vec3Lanes::splat(normal),
                        error: Floats::splat(planar_error(origin, edge1, edge2)),
                    }
                }
                _ => panic!("`FewShapes::takes` does not take {shape:?}"),
            })
            .collect();
        FewShapes { shapes, names }
    }

    /// Per lane, the nearest shape the ray meets in (0, t_max), with its hit record made in
    /// lanes: once per shape that is nearest in some lane.
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    pub fn closest(&self, rays: &RayLanes, t_max: Floats) -> Nearest {
        let mut t_nearest = t_max;
        // Positions in the list as floats (exact below 2^24), so one select updates them.
        let mut index = Floats::splat(-1.0);
        let mut st = [Floats::ZERO; 2];
        for (i, shape) in self.shapes.iter().enumerate() {
            let (t, shape_st) = shape.distances(rays);
            let hits = t.gt(Floats::ZERO) & t.lt(t_nearest);
            t_nearest = Real::select(hits, t, t_nearest);
            index = Real::select(hits, Floats::splat(i as f32), index);
            // Only planar shapes have coordinates; the others' lanes keep stale ones, unread.
            if let Some([s, u]) = shape_st {
                st = [Real::select(hits, s, st[0]), Real::select(hits, u, st[1])];
            }
        }
        let (mut point, mut normal, mut error) = (Vec3Lanes::ZERO, Vec3Lanes::ZERO, Floats::ZERO);
        let mut pending = index.ge(Floats::ZERO);
        while pending.any() {
            let i = index.lane(pending.bitmask().trailing_zeros() as usize);
            let same = index.eq(Floats::splat(i));
            let (p, n, e) = self.shapes[i as usize].hit(rays, t_nearest, st);
            point = Vec3Lanes::select(same, p, point);
            normal = Vec3Lanes::select(same, n, normal);
            error = Real::select(same, e, error);
            pending = pending & !same;
        }
        // Simple shapes shade with their geometric normal.
        let hits = HitLanes { point, normal, shading_normal: normal, error };
        Nearest {
            names: std::array::from_fn(|lane| {
                (index.lane(lane) >= 0.0).then(|| self.names[index.lane(lane) as usize])
            }),
            t: t_nearest,
            hits,
        }
    }

    /// Per lane, whether any shape meets the ray in (0, t_max).
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    pub fn any(&self, rays: &RayLanes, t_max: Floats) -> Mask {
        let mut occluded = Mask::none();
        for shape in &self.shapes {
            let t = shape.distances(rays).0;
            occluded = occluded | (t.gt(Floats::ZERO) & t.lt(t_max));
        }
        occluded
    }
}

impl Simple {
    /// Where the rays meet the shape at distance `t`, at coordinates `st` along the edges of a
    /// planar shape: the point, normal and error bound of `Shape::hit`, by its kernels.
    #[inline]
    fn hit(
        &self,
        rays: &RayLanes,
        t: Floats,
        [s, u]: [Floats; 2],
    ) -> (Vec3Lanes, Vec3Lanes, Floats) {
        let at = rays.origin + rays.dir * t;
        match self {
            Simple::Plane { normal, offset } => {
                let (point, error) = plane_point(*normal, *offset, at);
                (point, *normal, error)
            }
            Simple::Sphere { center, radius, error } => {
                let (point, normal) = sphere_point(*center, *radius, at);
                (point, normal, *error)
            }
            Simple::Planar { origin, edge1, edge2, normal, error, .. } => {
                (planar_point(*origin, *edge1, *edge2, s, u), *normal, *error)
            }
        }
    }

    /// The distances to the shape along the rays (NaN or out of range where there is no hit),
    /// and for planar shapes the coordinates along their edges.
    // Inlined into both integrators' loops over lanes (see `Scene::intersect_lanes`).
    #[inline(always)]
    fn distances(&self, rays: &RayLanes) -> (Floats, Option<[Floats; 2]>) {
        let (o, d) = (rays.origin, rays.dir);
        match self {
            Simple::Plane { normal, offset } => (plane_distance(*normal, *offset, o, d), None),
            Simple::Sphere { center, radius, .. } => {
                (sphere_distance(*center, *radius, o, d), None)
            }
            Simple::Planar { kind, hole, origin, edge1, edge2, .. } => {
                let (t, st) = planar_distance(*kind, *hole, *origin, *edge1, *edge2, o, d);
                (t, Some(st))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Cuboid, Ray};
    use crate::lanes::Wide;
    use crate::sampling::{Sampler, uniform_sphere};
    use glam::Vec3;

    /// The kernels are the one-ray tests' by construction; this holds what is FewShapes' own:
    /// the nearest per lane, the names, a box as its faces, `any` as `closest`.
    #[test]
    fn agrees_exactly_with_one_ray_and_one_shape_at_a_time() {
        // Planes of a box around the origin, spheres inside and across it, and each planar
        // kind (a disk with a hole too), some facing the other way.
        let mut shapes = vec![
            Shape::Plane { normal: Vec3::X, offset: 1.0 },
            Shape::Plane { normal: -Vec3::X, offset: 2.0 },
            Shape::Sphere { center: Vec3::ZERO, radius: 0.2 },
            Shape::Plane { normal: -Vec3::Y, offset: 1.0 },
            Shape::Sphere { center: Vec3::new(0.4, -0.3, 0.1), radius: 0.35 },
            Shape::Plane { normal: Vec3::new(1.0, 1.0, 0.0).normalize(), offset: 2.5 },
        ];
        let kinds = [PlanarKind::Triangle, PlanarKind::Quad, PlanarKind::Disk];
        for (k, kind) in kinds.into_iter().cycle().take(5).enumerate() {
            let origin = Vec3::new(0.1 * k as f32 - 0.3, 0.2, -0.1 * k as f32);
            let (edge1, edge2) = (Vec3::new(0.3, 0.1, 0.0), Vec3::new(0.0, 0.2, 0.4));
            let (edge1, edge2) = if k % 2 == 0 { (edge1, edge2) } else { (edge2, edge1) };
            let normal = edge1.cross(edge2).normalize();
            // The first disk with a hole (POV-Ray's disc with a hole radius).
            let hole = if k == 2 { 0.4 } else { 0.0 };
            shapes.push(Shape::Planar(Planar { kind, origin, edge1, edge2, normal, hole }));
        }
        // A box, as `scene::build` makes one: tested as its six faces.
        let (lo, size) = (Vec3::new(-0.2, -0.35, 0.05), Vec3::new(0.3, 0.2, 0.25));
        let [x, y, z] = [Vec3::X * size.x, Vec3::Y * size.y, Vec3::Z * size.z];
        let hi = lo + size;
        let quad = |origin, e1, e2| Planar::new(PlanarKind::Quad, origin, e1, e2);
        let faces = [
            quad(lo, z, y),
            quad(hi, -y, -z),
            quad(lo, x, z),
            quad(hi, -z, -x),
            quad(lo, y, x),
            quad(hi, -x, -y),
        ];
        let to_cube = glam::Affine3A::from_translation(lo) * glam::Affine3A::from_scale(size);
        shapes.push(Shape::Box(Box::new(Cuboid::new(faces, to_cube))));
        let few = FewShapes::new(shapes.iter().enumerate().map(|(i, shape)| (i as u32, shape)));
        let mut sampler = Sampler::new(4, 5, 6);
        let mut hits = [0; 3];
        for _ in 0..1000 {
            let rays: [Ray; LANES] = std::array::from_fn(|_| {
                let origin =
                    Vec3::new(sampler.next_1d(), sampler.next_1d(), sampler.next_1d()) - 0.5;
                Ray::new(origin, uniform_sphere(sampler.next_2d()))
            });
            let t_max = Floats::from_fn(|_| 4.0 * sampler.next_1d());
            let lanes = RayLanes::new(&rays);
            let nearest = few.closest(&lanes, t_max);
            let occluded = few.any(&lanes, t_max);
            for (lane, ray) in rays.iter().enumerate() {
                let one_by_one = shapes
                    .iter()
                    .enumerate()
                    .filter_map(|(i, shape)| {
                        let at = shape.intersection(ray, t_max.lane(lane))?;
                        Some(Hit { primitive: i as u32, ..shape.hit(ray, &at) })
                    })
                    .min_by(|a, b| a.t.total_cmp(&b.t));
                // The whole hit record, bit for bit.
                let key = |hit: Option<Hit>| {
                    hit.map(|h| (h.primitive, h.t, h.point, h.normal, h.shading_normal, h.error))
                };
                assert_eq!(key(nearest.hits()[lane]), key(one_by_one));
                assert_eq!(occluded.lane(lane), one_by_one.is_some());
                if let Some(i) = one_by_one.map(|h| h.primitive as usize) {
                    hits[match shapes[i] {
                        Shape::Plane { .. } => 0,
                        Shape::Sphere { .. } => 1,
                        _ => 2,
                    }] += 1;
                }
            }
        }
        assert!(hits.iter().all(|&n| n > 100), "every kind is hit often: {hits:?}");
    }
}
