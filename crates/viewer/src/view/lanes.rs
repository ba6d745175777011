//! The scene's other bodies (`[[bodies]]`) in the body's view: each on a lane of its own
//! across the ramp (body n at y = (n − 1) · spacing, beyond the scene's own body from the
//! camera), drawn in its colour ([`crate::colormap::body_colour`]), with its contact path on
//! the ramp in that colour. The lanes are only where the bodies are drawn: each body's run is
//! its own, and its y on the ramp is its run's plus its lane's.
//!
//! The camera frames every body shown while they are near enough together (at most
//! [`MAX_FRAMING_ZOOM`] times the usual distance); farther apart, it follows the scene's own
//! body, each other body is drawn beside it (a comparison of motions, not of a race), and the
//! overlay says how far ahead or behind each really is.

use glam::{DVec3, Mat4, Vec3};

use crate::colormap::{body_colour, linear};
use crate::geometry::Body;
use crate::geometry::mesh::{disk_mesh, sphere_mesh};
use crate::live::Snapshot;
use crate::render::types::{Material, MeshData, MeshHandle, MeshInstance, MeshStore, Segment};
use crate::scene::SceneSetup;

use super::body::push_polyline;
use super::{BODY_ICOSPHERE_LEVEL, CYLINDER_LENGTH, DISK_SEGMENTS};

/// The farthest the camera pulls back to keep every body in view, as a multiple of its usual
/// distance; past it, it follows the scene's own body.
pub const MAX_FRAMING_ZOOM: f32 = 3.5;

/// How much more steeply the camera looks down with other bodies shown (radians): the lanes,
/// across the ramp, are in depth to the usual camera, and the bodies hid one another.
pub const LANES_PITCH: f32 = 0.45;

/// How much further the camera turns uphill with other bodies shown (radians, about the
/// vertical): the lanes then spread across the screen rather than into it.
pub const LANES_YAW: f32 = -0.5;

/// Width of the ramp a group of bodies may take at the usual camera distance, in ⟨r⟩: the
/// 7 ⟨r⟩ camera's 40° field of view shows about 5 ⟨r⟩ at the body, less a margin for the
/// numbers and the insets at the sides.
const FRAMED_WIDTH: f64 = 4.0;

/// Where the view puts the bodies ([`LaneMeshes::placement`]).
pub(super) struct Placement {
    /// Where the camera looks, ramp coordinates.
    pub target: DVec3,
    /// How far back the camera stands, a multiple of its usual distance.
    pub zoom: f32,
    /// Added to each other body's position on the ramp.
    pub offsets: Vec<DVec3>,
    /// The other bodies are drawn beside the scene's own, not where they are along the ramp.
    pub aligned: bool,
    /// Added to the camera's elevation and turn (radians): [`LANES_PITCH`] and [`LANES_YAW`]
    /// while other bodies are shown, else none.
    pub pitch: f32,
    /// See `pitch`.
    pub yaw: f32,
}

/// The other bodies' meshes, uploaded once per scene, and their lanes' spacing.
pub(super) struct LaneMeshes {
    meshes: Vec<MeshHandle>,
    /// Distance between two lanes, in ⟨r⟩.
    spacing: f64,
}

impl LaneMeshes {
    /// Uploads each other body's mesh, in its colour (shaded, without the curvature map, so
    /// that the colour says which body it is).
    pub(super) fn new(renderer: &mut impl MeshStore, setup: &SceneSetup) -> Self {
        let mut widest = 1.0f64;
        let meshes = setup
            .lanes
            .iter()
            .enumerate()
            .map(|(i, lane)| {
                let mesh = match &lane.body {
                    Body::Sphere(s) => sphere_mesh(s, BODY_ICOSPHERE_LEVEL),
                    Body::Disk(d) => disk_mesh(d, DISK_SEGMENTS, CYLINDER_LENGTH),
                };
                for p in &mesh.positions {
                    widest = widest.max(f64::from(glam::Vec3::from_array(*p).length()));
                }
                let colour = linear(body_colour(i + 1), 1.0);
                renderer.upload_mesh(&MeshData {
                    positions: mesh.positions.clone(),
                    normals: mesh.normals.clone(),
                    colors: vec![colour; mesh.positions.len()],
                    indices: mesh.indices.clone(),
                })
            })
            .collect();
        let is_disk = matches!(setup.body, Body::Disk(_));
        Self {
            meshes,
            // A cylinder's length across the ramp, a sphere's diameter, and a gap.
            spacing: if is_disk {
                CYLINDER_LENGTH + 0.8
            } else {
                2.0 * widest + 0.8
            },
        }
    }

    /// Frees the meshes.
    pub(super) fn release(self, store: &mut impl MeshStore) {
        for mesh in self.meshes {
            store.free_mesh(mesh);
        }
    }

    /// Where body `n` (0: the scene's own) is drawn, added to its run's position on the ramp.
    pub(super) fn offset(&self, n: usize) -> DVec3 {
        DVec3::new(0.0, self.spacing * n as f64, 0.0)
    }

    /// Whether `snap`'s other bodies are drawn.
    pub(super) fn shown(&self, snap: &Snapshot) -> bool {
        snap.views.lanes && !snap.lanes.is_empty() && snap.lanes.len() == self.meshes.len()
    }

    /// How the bodies are placed in the view: where the camera looks (ramp coordinates), how
    /// far back it stands (a multiple of its usual distance), and what is added to each other
    /// body's position on the ramp. While every body fits within [`MAX_FRAMING_ZOOM`] each is
    /// where its run is, beside its lane; farther apart, each other body is drawn beside the
    /// scene's own (its distance along the ramp taken off, `aligned`), and the overlay says how
    /// far ahead or behind it really is.
    pub(super) fn placement(&self, snap: &Snapshot) -> Placement {
        let own = snap.pose.centre;
        let lane_offsets: Vec<DVec3> = (1..=snap.lanes.len()).map(|n| self.offset(n)).collect();
        if !self.shown(snap) {
            return Placement {
                target: own,
                zoom: 1.0,
                offsets: lane_offsets,
                aligned: false,
                pitch: 0.0,
                yaw: 0.0,
            };
        }
        let centres: Vec<DVec3> = std::iter::once(own)
            .chain(
                snap.lanes
                    .iter()
                    .zip(&lane_offsets)
                    .map(|(l, o)| l.pose.centre + *o),
            )
            .collect();
        let (lo, hi) = centres.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), c| (lo.min(*c), hi.max(*c)),
        );
        let span = (hi - lo).x.max((hi - lo).y) + self.spacing;
        let zoom = (span / FRAMED_WIDTH).max(1.0) as f32;
        if zoom <= MAX_FRAMING_ZOOM {
            return Placement {
                target: 0.5 * (lo + hi),
                zoom,
                offsets: lane_offsets,
                aligned: false,
                pitch: LANES_PITCH,
                yaw: LANES_YAW,
            };
        }
        let offsets: Vec<DVec3> = snap
            .lanes
            .iter()
            .zip(&lane_offsets)
            .map(|(l, o)| *o - DVec3::new(l.pose.centre.x - own.x, l.pose.centre.y - own.y, 0.0))
            .collect();
        let across = self.offset(snap.lanes.len()).y;
        Placement {
            target: DVec3::new(own.x, own.y + 0.5 * across, own.z),
            zoom: ((across + self.spacing) / FRAMED_WIDTH).max(1.0) as f32,
            offsets,
            aligned: true,
            pitch: LANES_PITCH,
            yaw: LANES_YAW,
        }
    }

    /// Where every body is drawn (world coordinates: the ramp turned by α), the scene's own
    /// first; empty when no other body is shown.
    pub(super) fn world_centres(&self, snap: &Snapshot) -> Vec<Vec3> {
        if !self.shown(snap) {
            return Vec::new();
        }
        let world_from_ramp = Mat4::from_rotation_y(snap.alpha_rad as f32);
        let placement = self.placement(snap);
        std::iter::once(snap.pose.centre)
            .chain(
                snap.lanes
                    .iter()
                    .zip(&placement.offsets)
                    .map(|(l, o)| l.pose.centre + *o),
            )
            .map(|c| world_from_ramp.transform_point3(c.as_vec3()))
            .collect()
    }

    /// The other bodies, their contact paths and (spheres) their contact rings, drawn through
    /// `to_world` (ramp to world) with `world_from_ramp`.
    pub(super) fn draw(
        &self,
        snap: &Snapshot,
        world_from_ramp: Mat4,
        to_world: impl Fn(DVec3) -> Vec3,
        on_face: impl Fn(DVec3) -> DVec3,
        is_disk: bool,
    ) -> (Vec<MeshInstance>, Vec<Segment>, Vec<Segment>) {
        let (mut meshes, mut segments, mut on_top) = (Vec::new(), Vec::new(), Vec::new());
        if !self.shown(snap) {
            return (meshes, segments, on_top);
        }
        let lift = DVec3::new(0.0, 0.0, 0.004);
        let placement = self.placement(snap);
        for (i, (lane, mesh)) in snap.lanes.iter().zip(&self.meshes).enumerate() {
            let offset = placement.offsets[i];
            let colour = body_colour(i + 1);
            meshes.push(MeshInstance {
                mesh: *mesh,
                model: world_from_ramp
                    * Mat4::from_rotation_translation(
                        lane.pose.rotation.as_quat(),
                        (lane.pose.centre + offset).as_vec3(),
                    ),
                material: Material::default(),
            });
            push_polyline(
                &mut segments,
                lane.ramp_trail
                    .iter()
                    .map(|&p| to_world(on_face(p) + offset + lift)),
                3.0,
                |age| linear(colour, 0.25 + 0.75 * age),
            );
            if !is_disk {
                let contact = lane.contact_on_ramp + offset + lift;
                let ring: Vec<Vec3> = (0..=32)
                    .map(|k| {
                        let a = std::f64::consts::TAU * f64::from(k) / 32.0;
                        to_world(contact + 0.12 * DVec3::new(a.cos(), a.sin(), 0.0))
                    })
                    .collect();
                on_top.extend(ring.windows(2).map(|w| Segment {
                    a: w[0],
                    b: w[1],
                    color: linear(colour, 0.9),
                    width_px: 3.0,
                }));
            }
        }
        (meshes, segments, on_top)
    }
}
