//! Triangle meshes of bodies, for drawing and for 3D printing: a subdivided icosahedron mapped
//! through r(u) (3D) or the cross-section r(θ) extruded into a capped cylinder (2D), with exact
//! normals and the curvature that colours each vertex, plus a binary STL writer.
//!
//! Written by hand rather than with a mesh crate because the vertex data comes from our own exact
//! r(u) derivatives (normal, Gaussian curvature) and all that is needed of the topology is the
//! icosahedron's subdivision (~60 lines). Pure math: imports `glam` only.
//!
//! Body frame of the 2D cylinder in 3D: the cross-section lies in the (x, z) plane, the point at
//! contact angle θ being r(θ)(cos θ, 0, sin θ), and the axis is y, from −length/2 to +length/2.

use std::collections::HashMap;
use std::f64::consts::TAU;
use std::io::{self, Write};

use glam::DVec3;

use super::{Disk, Sphere};

/// An indexed triangle mesh with one normal and one scalar (curvature) per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriMesh {
    /// Vertex positions in the body frame.
    pub positions: Vec<[f32; 3]>,
    /// Unit outward normals.
    pub normals: Vec<[f32; 3]>,
    /// The scalar that colours each vertex: Gaussian curvature K (3D), κ (2D). A cylinder's cap
    /// repeats κ of the rim on its rim vertices, so the section's turning shows end-on, and is
    /// NaN at its centre, where there is no curvature to show.
    pub values: Vec<f32>,
    /// Triangles, counter-clockwise seen from outside.
    pub indices: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Smallest and largest finite vertex value.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::geometry::mesh::sphere_mesh;
    /// // Every vertex of the unit sphere has K = 1.
    /// let (lo, hi) = sphere_mesh(&Sphere::perfect(), 2).value_range();
    /// assert!((lo - 1.0).abs() < 1e-6 && (hi - 1.0).abs() < 1e-6);
    /// ```
    pub fn value_range(&self) -> (f32, f32) {
        self.values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// Volume enclosed (divergence theorem); positive when the triangles face outward.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::geometry::mesh::sphere_mesh;
    /// // The inscribed polyhedron approaches 4π/3 from below.
    /// let v = sphere_mesh(&Sphere::perfect(), 4).volume();
    /// let ball = 4.0 / 3.0 * std::f64::consts::PI;
    /// assert!(v < ball && v > 0.99 * ball);
    /// ```
    pub fn volume(&self) -> f64 {
        self.indices
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| as_dvec(self.positions[i as usize]));
                a.dot(b.cross(c)) / 6.0
            })
            .sum()
    }

    /// The solid's own convex hull about its volume centroid, and the α* its facets give
    /// ([`super::solid_hull`]): what a print of this mesh rests up to, in the mesh's units.
    /// `None` for a mesh with no volume.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::geometry::mesh::sphere_mesh;
    /// // A round ball's icosphere of 1,280 triangles rests on a facet up to about 5.5°.
    /// let hull = sphere_mesh(&Sphere::perfect(), 3).printed_hull().unwrap();
    /// assert!(hull.alpha_star > 0.09 && hull.alpha_star < 0.1, "{hull:?}");
    /// ```
    pub fn printed_hull(&self) -> Option<super::solid_hull::SolidHull> {
        let (mut volume, mut moment) = (0.0, DVec3::ZERO);
        for t in &self.indices {
            let [a, b, c] = t.map(|i| as_dvec(self.positions[i as usize]));
            let v = a.dot(b.cross(c)) / 6.0;
            volume += v;
            moment += v * (a + b + c) / 4.0;
        }
        if volume == 0.0 || !volume.is_finite() {
            return None;
        }
        let points: Vec<DVec3> = self.positions.iter().map(|&p| as_dvec(p)).collect();
        super::solid_hull::solid_hull(&points, moment / volume)
    }

    /// Edges that are not shared by exactly two triangles in opposite directions, after
    /// welding vertices with identical positions. Zero means the surface is closed and
    /// consistently oriented (watertight), which a slicer for 3D printing needs.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Disk;
    /// use rollphase_core::geometry::mesh::disk_mesh;
    /// assert_eq!(disk_mesh(&Disk::perfect(), 64, 1.0).open_edges(), 0);
    /// ```
    pub fn open_edges(&self) -> usize {
        let mut weld: HashMap<[u32; 3], u32> = HashMap::new();
        let ids: Vec<u32> = self
            .positions
            .iter()
            .map(|p| {
                let key = p.map(f32::to_bits);
                let n = weld.len() as u32;
                *weld.entry(key).or_insert(n)
            })
            .collect();
        let mut directed: HashMap<(u32, u32), i32> = HashMap::new();
        for t in &self.indices {
            let v = t.map(|i| ids[i as usize]);
            for k in 0..3 {
                let (a, b) = (v[k], v[(k + 1) % 3]);
                *directed.entry((a, b)).or_default() += 1;
            }
        }
        directed
            .iter()
            .filter(|&(&(a, b), &n)| n != 1 || directed.get(&(b, a)) != Some(&1))
            .count()
    }

    /// Writes binary STL with every coordinate multiplied by `scale` (e.g. millimetres per ⟨r⟩).
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::geometry::mesh::sphere_mesh;
    /// let mesh = sphere_mesh(&Sphere::perfect(), 1);
    /// let mut stl = Vec::new();
    /// mesh.write_stl(&mut stl, 10.0, "ball")?;
    /// // 80-byte header, a count, then 50 bytes a triangle.
    /// assert_eq!(stl.len(), 84 + 50 * mesh.indices.len());
    /// # Ok::<(), std::io::Error>(())
    /// ```
    pub fn write_stl(&self, out: &mut impl Write, scale: f64, solid_name: &str) -> io::Result<()> {
        let mut header = [b' '; 80];
        let text = format!("rollphase {solid_name}");
        let n = text.len().min(80);
        header[..n].copy_from_slice(&text.as_bytes()[..n]);
        out.write_all(&header)?;
        out.write_all(&(self.indices.len() as u32).to_le_bytes())?;
        for t in &self.indices {
            let [a, b, c] = t.map(|i| as_dvec(self.positions[i as usize]) * scale);
            let n = (b - a).cross(c - a).normalize_or_zero();
            for v in [n, a, b, c] {
                for x in [v.x, v.y, v.z] {
                    out.write_all(&(x as f32).to_le_bytes())?;
                }
            }
            out.write_all(&0u16.to_le_bytes())?;
        }
        Ok(())
    }

    /// Writes binary little-endian PLY, the indexed form scanners write: each vertex once
    /// (x, y, z as f32, multiplied by `scale` exactly as [`Self::write_stl`] does, so the two
    /// files hold the same triangles to the bit), then each triangle as three vertex indices.
    ///
    /// # Example
    /// ```
    /// use rollphase_core::geometry::Sphere;
    /// use rollphase_core::geometry::mesh::sphere_mesh;
    /// let mesh = sphere_mesh(&Sphere::perfect(), 1);
    /// let mut ply = Vec::new();
    /// mesh.write_ply(&mut ply, 10.0)?;
    /// let header_end = ply.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
    /// // 12 bytes a vertex, then a count byte and three 4-byte indices a triangle.
    /// assert_eq!(ply.len() - header_end, 12 * mesh.positions.len() + 13 * mesh.indices.len());
    /// # Ok::<(), std::io::Error>(())
    /// ```
    pub fn write_ply(&self, out: &mut impl Write, scale: f64) -> io::Result<()> {
        write!(
            out,
            "ply\nformat binary_little_endian 1.0\ncomment rollphase\nelement vertex {}\n\
             property float x\nproperty float y\nproperty float z\nelement face {}\n\
             property list uchar uint vertex_indices\nend_header\n",
            self.positions.len(),
            self.indices.len()
        )?;
        for &p in &self.positions {
            for x in as_f32(as_dvec(p) * scale) {
                out.write_all(&x.to_le_bytes())?;
            }
        }
        for t in &self.indices {
            out.write_all(&[3])?;
            for i in t {
                out.write_all(&i.to_le_bytes())?;
            }
        }
        Ok(())
    }
}

fn as_dvec(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

fn as_f32(v: DVec3) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The unit icosphere: an icosahedron subdivided `level` times (10·4^level + 2 vertices),
/// vertices on the unit sphere, triangles counter-clockwise from outside.
///
/// # Example
/// ```
/// use rollphase_core::geometry::mesh::icosphere;
/// let (vertices, triangles) = icosphere(2);
/// assert_eq!((vertices.len(), triangles.len()), (162, 320));
/// assert!(vertices.iter().all(|v| (v.length() - 1.0).abs() < 1e-14));
/// ```
pub fn icosphere(level: u32) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut verts: Vec<DVec3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| DVec3::new(x, y, z).normalize())
    .collect();
    let mut tris: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut midpoint: HashMap<(u32, u32), u32> = HashMap::new();
        let mut mid = |a: u32, b: u32, verts: &mut Vec<DVec3>| {
            *midpoint.entry((a.min(b), a.max(b))).or_insert_with(|| {
                verts.push((verts[a as usize] + verts[b as usize]).normalize());
                verts.len() as u32 - 1
            })
        };
        let mut next = Vec::with_capacity(tris.len() * 4);
        for [a, b, c] in tris {
            let ab = mid(a, b, &mut verts);
            let bc = mid(b, c, &mut verts);
            let ca = mid(c, a, &mut verts);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        tris = next;
    }
    (verts, tris)
}

/// The 3D body as a closed mesh: icosphere directions u mapped to r(u)·u, with the exact
/// outward normal and Gaussian curvature K of the surface at each vertex.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Body, mesh::sphere_mesh};
/// let Body::Sphere(s) = Body::paper_sphere(219, 0.25, 5)? else { unreachable!() };
/// let mesh = sphere_mesh(&s, 3);
/// assert_eq!(mesh.open_edges(), 0);
/// // A convex body: K > 0 at every vertex.
/// assert!(mesh.value_range().0 > 0.0);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn sphere_mesh(body: &Sphere, level: u32) -> TriMesh {
    let (dirs, indices) = icosphere(level);
    let mut mesh = TriMesh {
        indices,
        ..TriMesh::default()
    };
    for u in dirs {
        let s = body.surface(u);
        mesh.positions.push(as_f32(s.p));
        mesh.normals.push(as_f32(s.normal));
        mesh.values.push(s.gaussian_curvature() as f32);
    }
    mesh
}

/// Segments around a 2D body for a mesh that is printed: at least `min`, doubled (up to
/// 65,536) until the printed polygon rests no steeper than the body itself, within half of
/// [`super::facets::FACET_TOLERANCE`] (0.05°). A polygon of N equal steps sits flat on its
/// sides up to about π/N beyond the body's own α*, so 1,024 segments raise a printed
/// cylinder's α* by about 0.17°, more than an inclinometer resolves. `alpha_star` is the
/// body's own ([`crate::analysis::critical_angle`]).
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Disk, mesh::print_segments};
/// // A circle: π/N must fall below 0.05°, so N ≥ 4096.
/// assert_eq!(print_segments(&Disk::perfect(), 0.0, 1024), 4096);
/// ```
pub fn print_segments(body: &Disk, alpha_star: f64, min: usize) -> usize {
    let mut n = min.max(8);
    while n < 1 << 16 {
        let ring: Vec<[f64; 2]> = (0..n)
            .map(|i| {
                let theta = TAU * i as f64 / n as f64;
                let r = body.jet(theta).r;
                [r * theta.cos(), r * theta.sin()]
            })
            .collect();
        let printed = super::facets::section_hull(&ring).map_or(f64::INFINITY, |h| h.alpha_star);
        if (printed - alpha_star).abs() <= 0.5 * super::facets::FACET_TOLERANCE {
            break;
        }
        n *= 2;
    }
    n
}

/// What [`TriMesh::write_stl`]'s header says of a [`disk_mesh`] beside its name: its axis, with
/// θ counter-clockwise seen from that end. The mesh fit reads it back ([`stl_header_axis`]), so
/// that an exported cylinder is not fitted as its mirror image, which a mesh alone cannot tell
/// from it (turned end for end, the section's θ runs the other way).
pub const DISK_AXIS_TAG: &str = "axis=0,-1,0";

/// The axis an STL header written by rollphase names (`axis=X,Y,Z`), if any.
///
/// # Example
/// ```
/// use rollphase_core::geometry::mesh::{DISK_AXIS_TAG, stl_header_axis};
/// let header = format!("rollphase cylinder {DISK_AXIS_TAG}");
/// assert_eq!(stl_header_axis(&header), Some([0.0, -1.0, 0.0]));
/// assert_eq!(stl_header_axis("solid made by a CAD tool"), None);
/// ```
pub fn stl_header_axis(header: &str) -> Option<[f64; 3]> {
    if !header.starts_with("rollphase ") {
        return None;
    }
    let tag = header
        .split_whitespace()
        .find_map(|w| w.strip_prefix("axis="))?;
    let v: Vec<f64> = tag
        .split(',')
        .map(|c| c.parse().ok())
        .collect::<Option<_>>()?;
    let a: [f64; 3] = v.try_into().ok()?;
    (a.iter().all(|c| c.is_finite()) && a.iter().any(|c| *c != 0.0)).then_some(a)
}

/// The mesh a body is printed from: a 3D body's icosphere at `detail` (1–8), a cylinder's
/// section fine enough that the polygon's flats do not raise α* (0.05°), `length` long in ⟨r⟩.
/// Both `rollphase export-stl` and the app's "Save STL" write this mesh.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Body, mesh::print_mesh};
/// let mesh = print_mesh(&Body::random_disk(1, 0.1, 5)?, 3, 2.0);
/// assert_eq!(mesh.open_edges(), 0);
/// # Ok::<(), rollphase_core::geometry::ShapeError>(())
/// ```
pub fn print_mesh(body: &super::Body, detail: u32, length: f64) -> TriMesh {
    match body {
        super::Body::Sphere(s) => sphere_mesh(s, detail),
        super::Body::Disk(d) => {
            let segments = print_segments(d, body.alpha_star(), 16 << detail);
            disk_mesh(d, segments, length)
        }
    }
}

/// The 2D body as a closed cylinder of the given length: `segments` points around r(θ) (side
/// coloured by κ), flat caps. Rim vertices are duplicated (side and cap normals differ) at
/// bit-identical positions, so the welded surface is watertight.
///
/// # Example
/// ```
/// use rollphase_core::geometry::{Disk, mesh::disk_mesh};
/// // A cylinder of radius 1 and length 2: volume 2π (less the polygon's shortfall).
/// let v = disk_mesh(&Disk::perfect(), 256, 2.0).volume();
/// assert!((v - 2.0 * std::f64::consts::PI).abs() < 1e-3);
/// ```
pub fn disk_mesh(body: &Disk, segments: usize, length: f64) -> TriMesh {
    let n = segments.max(8);
    let half = length / 2.0;
    let mut mesh = TriMesh::default();
    let ring: Vec<(DVec3, DVec3, f64)> = (0..n)
        .map(|i| {
            let theta = TAU * i as f64 / n as f64;
            let j = body.jet(theta);
            let (s, c) = theta.sin_cos();
            let p = DVec3::new(j.r * c, 0.0, j.r * s);
            // Outward normal of the curve (r cos θ, r sin θ): rotate the tangent by −90°.
            let tangent = DVec3::new(j.r1 * c - j.r * s, 0.0, j.r1 * s + j.r * c);
            let normal = DVec3::new(tangent.z, 0.0, -tangent.x).normalize();
            (p, normal, j.curvature())
        })
        .collect();
    let push = |mesh: &mut TriMesh, p: DVec3, nrm: DVec3, v: f32| {
        mesh.positions.push(as_f32(p));
        mesh.normals.push(as_f32(nrm));
        mesh.values.push(v);
        mesh.positions.len() as u32 - 1
    };
    // Side: two rings.
    let side0 = mesh.positions.len() as u32;
    for &(p, nrm, k) in &ring {
        push(&mut mesh, p - DVec3::Y * half, nrm, k as f32);
        push(&mut mesh, p + DVec3::Y * half, nrm, k as f32);
    }
    for i in 0..n as u32 {
        let j = (i + 1) % n as u32;
        let (a0, a1) = (side0 + 2 * i, side0 + 2 * i + 1);
        let (b0, b1) = (side0 + 2 * j, side0 + 2 * j + 1);
        // θ increases from +x towards +z, which seen from outside runs clockwise about +y.
        mesh.indices.push([a0, a1, b0]);
        mesh.indices.push([b0, a1, b1]);
    }
    // Caps: fans from the axis (valid because the section is star-shaped about it).
    for (side, normal) in [(-half, -DVec3::Y), (half, DVec3::Y)] {
        let centre = push(&mut mesh, DVec3::Y * side, normal, f32::NAN);
        let first = mesh.positions.len() as u32;
        for &(p, _, k) in &ring {
            push(&mut mesh, p + DVec3::Y * side, normal, k as f32);
        }
        for i in 0..n as u32 {
            let (a, b) = (first + i, first + (i + 1) % n as u32);
            if side < 0.0 {
                mesh.indices.push([centre, a, b]);
            } else {
                mesh.indices.push([centre, b, a]);
            }
        }
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{random_disk, random_sphere};

    #[test]
    fn icosphere_counts_follow_the_subdivision_law() {
        for level in 0..4 {
            let (v, t) = icosphere(level);
            assert_eq!(v.len(), 10 * 4usize.pow(level) + 2);
            assert_eq!(t.len(), 20 * 4usize.pow(level));
        }
    }

    #[test]
    fn perfect_sphere_mesh_is_closed_outward_and_has_unit_curvature() {
        let m = sphere_mesh(&Sphere::perfect(), 4);
        assert_eq!(m.open_edges(), 0);
        let exact = 4.0 / 3.0 * std::f64::consts::PI;
        // An inscribed polyhedron: volume short of the ball by O(h²), h ≈ 0.06 at level 4.
        let v = m.volume();
        assert!(v > 0.99 * exact && v < exact, "volume {v} vs {exact}");
        let (lo, hi) = m.value_range();
        assert!((lo - 1.0).abs() < 1e-5 && (hi - 1.0).abs() < 1e-5);
    }

    #[test]
    fn random_bodies_give_watertight_meshes_with_varying_curvature() {
        let s = sphere_mesh(&random_sphere(1, 1.0, 5).unwrap(), 3);
        assert_eq!(s.open_edges(), 0);
        assert!(s.volume() > 0.0);
        let (lo, hi) = s.value_range();
        assert!(hi - lo > 0.1, "K range {lo}..{hi}");
        let d = disk_mesh(&random_disk(3, 1.0, 5).unwrap(), 128, 1.0);
        assert_eq!(d.open_edges(), 0);
        // Volume = length × area of the section, area = ½∮r² dθ ≈ π for ⟨r⟩ = 1.
        assert!((d.volume() - std::f64::consts::PI).abs() < 0.2);
    }

    #[test]
    fn perfect_disk_mesh_matches_the_cylinder() {
        let d = disk_mesh(&Disk::perfect(), 256, 2.0);
        assert_eq!(d.open_edges(), 0);
        let exact = 2.0 * std::f64::consts::PI;
        let polygon = 2.0 * 256.0 * 0.5 * (TAU / 256.0).sin();
        assert!((d.volume() - polygon).abs() < 1e-5 * exact);
        let (lo, hi) = d.value_range();
        assert!((lo - 1.0).abs() < 1e-6 && (hi - 1.0).abs() < 1e-6);
    }

    #[test]
    fn stl_has_the_declared_size_and_scaled_coordinates() {
        let m = sphere_mesh(&Sphere::perfect(), 1);
        let mut bytes = Vec::new();
        m.write_stl(&mut bytes, 25.0, "test").unwrap();
        assert_eq!(bytes.len(), 84 + 50 * m.indices.len());
        let n = u32::from_le_bytes(bytes[80..84].try_into().unwrap());
        assert_eq!(n as usize, m.indices.len());
        let x = f32::from_le_bytes(bytes[96..100].try_into().unwrap());
        let y = f32::from_le_bytes(bytes[100..104].try_into().unwrap());
        let z = f32::from_le_bytes(bytes[104..108].try_into().unwrap());
        assert!(((x * x + y * y + z * z).sqrt() - 25.0).abs() < 1e-3);
    }
}
