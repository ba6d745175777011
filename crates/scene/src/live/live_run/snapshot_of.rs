//! [`LiveRun::snapshot`]: what a frame shows of the run, drawn from its state and what its
//! steps recorded up to the time shown (trails, the crossings of the section and the cycle they
//! decide, the contact force and the first violation, each other body's own snapshot).

use glam::{DQuat, DVec3};

use super::super::snapshot::*;
use super::{
    Crossing, LIVE_REST_THRESHOLD, LiveRun, MAX_MULTIPLICITY, MULTIPLICITY_TOL, TrailSample,
    at_rest_within, ball_point, observe, settled_cycle,
};

impl LiveRun {
    /// What the current state looks like.
    pub fn snapshot(&self) -> Snapshot {
        let o = observe(&self.state, &self.ramp);
        // What the steps have recorded past the time shown waits for its frame.
        let trail: Vec<&TrailSample> = self.trail.iter().filter(|s| s.t <= self.t).collect();
        let crossings: Vec<&(f64, Option<DVec3>)> =
            self.crossings.iter().filter(|c| c.0 <= self.t).collect();
        let mut ball_trail: Vec<Vec<DVec3>> = Vec::new();
        if self.track_ball {
            let mut prev: Option<DQuat> = None;
            for s in trail.iter().filter_map(|s| s.ball) {
                // Start a new piece where q_w changes sign: there the drawn point (q_w ≥ 0)
                // jumps to the antipode, and a chord through the ball would be false.
                let jump = prev.is_none_or(|p| (p.w >= 0.0) != (s.w >= 0.0));
                if jump {
                    ball_trail.push(Vec::new());
                }
                if let Some(piece) = ball_trail.last_mut() {
                    piece.push(ball_point(s));
                }
                prev = Some(s);
            }
        }
        let n = crossings.len();
        let period = (n >= 2).then(|| crossings[n - 1].0 - crossings[n - 2].0);
        let section: Vec<Crossing> = crossings
            .iter()
            .filter_map(|(t, p)| {
                Some(Crossing {
                    t: *t,
                    point: (*p)?.to_array(),
                })
            })
            .collect();
        // The one test of a repeat that `predict` and the sweeps use: a cycle of k ≥ 2 must also
        // be steady, so a period-1 orbit still alternating near a flip is not shown doubled.
        let cycle = settled_cycle(&section, MAX_MULTIPLICITY, MULTIPLICITY_TOL);
        let period_multiplicity = cycle.map(|c| c.0);
        let cycle_crossings = period_multiplicity.map_or_else(Vec::new, |k| {
            section[section.len() - (2 * k + 1)..]
                .iter()
                .map(|c| (c.t, DVec3::from_array(c.point)))
                .collect()
        });
        Snapshot {
            state: self.state.vector().to_vec(),
            t: self.t,
            model: self.state.kind(),
            integrator: self.method.name(),
            alpha_rad: self.ramp.alpha_rad,
            alpha_star: self.setup.alpha_star,
            mass_ratio: self.ramp.mass_ratio,
            drag_law: self.ramp.drag_law,
            pose: o.pose,
            contact_on_ramp: o.on_ramp,
            contact_in_body: o.in_body,
            ramp_trail: trail.iter().map(|s| s.on_ramp).collect(),
            body_trail: trail.iter().map(|s| s.in_body).collect(),
            ball_trail,
            ball_point: if self.track_ball {
                o.ball.map(ball_point)
            } else {
                None
            },
            period,
            period_multiplicity,
            cycle_period: cycle.map(|c| c.1),
            cycle_crossings,
            last_crossing_t: crossings.last().map(|c| c.0),
            halted: at_rest_within(o.angular_speed, o.ramp_torque, LIVE_REST_THRESHOLD),
            angular_speed: o.angular_speed,
            theta_dot: o.theta_dot,
            theta: o.theta,
            health: self.health,
            stopped: self.stopped.clone(),
            contact_force: o.force,
            contact: self.contact.report(),
            validity: self
                .contact
                .report()
                .violations()
                .first()
                .filter(|v| v.t() <= self.t)
                .map(|v| v.headline()),
            hull_tips: self.hull_tips,
            views: self.setup.scene.views.clone(),
            caption: self.caption.clone(),
            lesson: (!self.setup.timeline.is_empty()).then(|| LessonProgress {
                done: self.steps_done,
                steps: self.setup.timeline.len(),
                next_at: self.next_step_time(),
            }),
            poincare_field: self.field_wanted(),
            off_script: self.off_script,
            replay: self.replay.clone(),
            label: if self.setup.scene.label.is_empty() {
                self.setup.scene.name.clone()
            } else {
                self.setup.scene.label.clone()
            },
            lanes: self
                .lanes
                .iter()
                .zip(&self.lanes_share_body)
                .map(|(lane, &shares_body)| Snapshot {
                    shares_body,
                    ..lane.snapshot()
                })
                .collect(),
            shares_body: true,
            drag_gamma: self.ramp.drag,
        }
    }
}
