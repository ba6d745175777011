//! A sculpting drag: from a press on the body, the pointer's height above or below the press is
//! the stroke's height (up pulls the surface out, down presses it in). Every move sculpts the
//! body as it was when the drag began again, from the session as it was then, and restarts the
//! run from that moment's contact, so the readout follows live, moving back takes the stroke
//! back, and the release keeps one stroke (one undo; a drag that ends where it began leaves the
//! history as it was, redo included). A drag past the edge of convexity stops at the edge,
//! found by halving, and says why. A restart refused mid-drag ends the drag on the body before
//! it, with why.

use super::super::{AppUi, UiAction};
use super::{PRINT_DROPPED, contact_now};
use crate::geometry::Body;
use crate::geometry::sculpt::{MAX_STROKE_HEIGHT, SculptError, Stroke, StrokePoint, sculpt};
use crate::live::{SimCommand, SimStatus};
use crate::scene::InitialSpec;
use crate::scene::sculpt::Sculptor;

/// How far a drag moves the surface per screen point the pointer moves up (pull) or down
/// (press), in ⟨r⟩: 100 points make 0.05, and the largest stroke is 600 points away.
pub const DRAG_HEIGHT_PER_POINT: f64 = 5e-4;

/// How much a drag's height must change before the body is sculpted again and the run restarted
/// (⟨r⟩): below a hundredth of a millimetre at the usual print scales, and a few moves per point
/// of pointer travel at most.
const DRAG_HEIGHT_STEP: f64 = 2e-4;

/// Halvings of the search for the edge of convexity when a drag goes past it: the edge is found
/// to 2⁻¹² of the way from the last height taken to the one refused.
const EDGE_HALVINGS: u32 = 12;

/// The drag's bodies sent and not yet shown that are remembered: far more than the moves of the
/// few frames a load takes to arrive.
const MAX_IN_FLIGHT: usize = 64;

/// A stroke being dragged: where it was pressed, what the body and the session were when the
/// drag began, and the height it has now.
pub(super) struct DragStroke {
    at: StrokePoint,
    /// The press's height on the screen (points): the height follows the pointer from there.
    origin_y: f32,
    /// The body before the drag.
    base: Body,
    /// α* before the drag.
    base_alpha_star: f64,
    /// The session before the drag: each move starts from it again.
    session_before: Sculptor,
    /// The contact every restart starts from: the run's when the drag began.
    initial: InitialSpec,
    /// Whether the body before the drag was a print's section (the notice says it is dropped).
    printed: bool,
    /// The height the running body has (0: the body before the drag).
    height: f64,
    /// Once a height was refused: the largest height of that sign taken, the smallest refused,
    /// and why (heights past it are not tried again: the base does not change during a drag).
    edge: Option<(f64, f64, String)>,
}

impl AppUi {
    /// A press at frame pixel (`x`, `y`) of the scene area that became a drag while sculpting,
    /// pressed at `origin_y` (screen points): the drag sculpts if the body is under the press and
    /// the scene may be sculpted. Otherwise the notice says why, or (off the body) the drag turns
    /// the camera, as without sculpting.
    pub(in crate::ui) fn sculpt_drag_start(
        &mut self,
        (x, y): (f32, f32),
        origin_y: f32,
        status: &SimStatus,
    ) {
        let Ok(Some(at)) = self.sculptable_point((x, y), status) else {
            return;
        };
        let Some(session) = self.sculpt.session.clone() else {
            return;
        };
        let initial = contact_now(status);
        // Refused for the whole drag (a lesson, for one): said once, at its start.
        if let Err(e) = self.sculpted_setup(session.body(), initial.clone(), status) {
            self.notice = Some((e.to_string(), true));
            return;
        }
        self.sculpt.dragging = Some(DragStroke {
            at,
            origin_y,
            base: session.body().clone(),
            base_alpha_star: status.setup.alpha_star,
            session_before: session,
            initial,
            printed: matches!(&status.setup.body, Body::Disk(d) if d.printed_section().is_some()),
            height: 0.0,
            edge: None,
        });
        self.notice = Some((
            "drag up to pull the surface out, down to press it in; release to keep".into(),
            false,
        ));
    }

    /// The pointer of a sculpting drag is at height `y` (screen points): the body before the drag
    /// with the stroke of that height, run from the drag's contact, unless the height moved by
    /// less than [`DRAG_HEIGHT_STEP`]. Past the edge of convexity the stroke stops at the edge
    /// (found by halving) and the notice says why.
    pub(in crate::ui) fn sculpt_drag_move(
        &mut self,
        y: f32,
        status: &SimStatus,
        actions: &mut Vec<UiAction>,
    ) {
        let width = self.sculpt.width;
        let Some(drag) = self.sculpt.dragging.as_mut() else {
            return;
        };
        let wanted = (f64::from(drag.origin_y - y) * DRAG_HEIGHT_PER_POINT)
            .clamp(-MAX_STROKE_HEIGHT, MAX_STROKE_HEIGHT);
        let past_edge = |edge: &Option<(f64, f64, String)>| {
            edge.as_ref().is_some_and(|(_, refused, _)| {
                wanted * refused > 0.0 && wanted.abs() >= refused.abs()
            })
        };
        let height = match &drag.edge {
            Some((taken, ..)) if past_edge(&drag.edge) => *taken,
            _ if wanted.abs() < DRAG_HEIGHT_STEP / 2.0 => 0.0,
            _ => wanted,
        };
        if height == drag.height || height != 0.0 && (height - drag.height).abs() < DRAG_HEIGHT_STEP
        {
            return;
        }
        let stroke = |height| Stroke {
            at: drag.at,
            width,
            height,
        };
        let tried = if height == 0.0 {
            Ok(drag.base.clone())
        } else {
            sculpt(&drag.base, &stroke(height))
        };
        let (height, body) = match tried {
            Ok(body) => (height, body),
            Err(SculptError::NotConvex(why)) => {
                // The last height of this sign taken is convex; halve toward the refused one.
                let from = if drag.height * height > 0.0 {
                    drag.height
                } else {
                    0.0
                };
                let (taken, refused) =
                    edge_of_convexity(from, height, |h| sculpt(&drag.base, &stroke(h)).is_ok());
                drag.edge = Some((taken, refused, why.to_string()));
                let body = match taken {
                    0.0 => Ok(drag.base.clone()),
                    h => sculpt(&drag.base, &stroke(h)),
                };
                match body {
                    Ok(body) if taken != drag.height => (taken, body),
                    _ => {
                        // Already at the edge: nothing to restart, but say why it stops.
                        let (h, edge) = (drag.height, drag.edge.clone());
                        self.say_drag(h, None, edge.map(|(_, r, w)| (r, w)));
                        return;
                    }
                }
            }
            Err(e) => {
                self.notice = Some((e.to_string(), true));
                return;
            }
        };
        // At the edge: held at it (a body already at the edge stays at 0 past it).
        let at_edge = drag
            .edge
            .as_ref()
            .filter(|(taken, ..)| *taken == height && (height != 0.0 || past_edge(&drag.edge)))
            .map(|(_, refused, why)| (*refused, why.clone()));
        let mut session = drag.session_before.clone();
        if height != 0.0
            && let Err(e) = session.set_body(body.clone())
        {
            self.drag_refused(e.to_string(), status, actions);
            return;
        }
        let (base_alpha_star, initial) = (drag.base_alpha_star, drag.initial.clone());
        drag.height = height;
        self.sculpt.session = Some(session);
        match self.sculpted_setup(&body, initial, status) {
            Ok(setup) => {
                let alpha_star = setup.alpha_star;
                self.send_drag_body(&body, setup, actions);
                self.say_drag(height, Some((base_alpha_star, alpha_star)), at_edge);
            }
            Err(e) => self.drag_refused(e.to_string(), status, actions),
        }
    }

    /// Sends the run of a drag's `body`, remembering it as the drag's while it is on its way.
    fn send_drag_body(
        &mut self,
        body: &Body,
        setup: crate::scene::SceneSetup,
        actions: &mut Vec<UiAction>,
    ) {
        let in_flight = &mut self.sculpt.in_flight;
        in_flight.push(body.to_shape());
        if in_flight.len() > MAX_IN_FLIGHT {
            in_flight.remove(0);
        }
        actions.push(UiAction::Sim(SimCommand::Load(Box::new(setup))));
    }

    /// A restart refused in the middle of a drag: the drag ends, the session and the run go back
    /// to the body before it, and the notice says why.
    fn drag_refused(&mut self, why: String, status: &SimStatus, actions: &mut Vec<UiAction>) {
        let Some(drag) = self.sculpt.dragging.take() else {
            return;
        };
        self.sculpt.session = Some(drag.session_before);
        if drag.height != 0.0
            && let Ok(setup) = self.sculpted_setup(&drag.base, drag.initial, status)
        {
            self.send_drag_body(&drag.base, setup, actions);
        }
        self.notice = Some((
            format!("the drag is undone, the body is as before it: {why}"),
            true,
        ));
    }

    /// The notice while a drag sculpts: the height, α* before and now, and the edge of
    /// convexity (the height refused, and why) if the drag is held past it.
    fn say_drag(
        &mut self,
        height: f64,
        alpha_stars: Option<(f64, f64)>,
        edge: Option<(f64, String)>,
    ) {
        let printed = self.sculpt.dragging.as_ref().is_some_and(|d| d.printed);
        let what = if height > 0.0 {
            format!("pulling a bump out by {height:.4} mean r")
        } else if height < 0.0 {
            format!("pressing a dent in by {:.4} mean r", -height)
        } else {
            "the body before the drag".into()
        };
        let alpha = alpha_stars.map_or(String::new(), |(a, b)| format!("; α* {a:.5} → {b:.5} rad"));
        let print = if printed && height != 0.0 {
            PRINT_DROPPED
        } else {
            ""
        };
        self.notice = Some(match edge {
            Some((refused, why)) => (
                format!(
                    "{what}{alpha}{print}: the edge of convexity — a {} of {:.4} mean r would \
                     leave the body not strictly convex ({why}); release to keep",
                    if refused > 0.0 { "bump" } else { "dent" },
                    refused.abs()
                ),
                true,
            ),
            None => (format!("{what}{alpha}{print}; release to keep"), false),
        });
    }

    /// The release of a sculpting drag: the body it made is kept as one stroke (one undo), or,
    /// ended where it began, the session is as it was before the drag (redo included).
    pub(in crate::ui) fn sculpt_drag_end(&mut self) {
        let Some(drag) = self.sculpt.dragging.take() else {
            return;
        };
        let h = drag.height;
        let kind = if h > 0.0 {
            "pulled a bump"
        } else {
            "pressed a dent"
        };
        let text = match &drag.edge {
            _ if h == 0.0 => {
                self.sculpt.session = Some(drag.session_before);
                "the drag ended where it began: the body is as before".to_string()
            }
            Some((taken, _, why)) if *taken == h => format!(
                "{kind} by {:.4} mean r, at the edge of convexity ({why}); Ctrl+Z undoes",
                h.abs()
            ),
            _ => format!("{kind} by {:.4} mean r; Ctrl+Z undoes", h.abs()),
        };
        self.notice = Some((text, false));
    }

    /// Whether a drag is sculpting (the camera stays put meanwhile).
    pub fn sculpt_dragging(&self) -> bool {
        self.sculpt.dragging.is_some()
    }
}

/// The edge of convexity between a height `taken` (convex; 0 is the body itself) and a height
/// `refused` of the same sign, by halving [`EDGE_HALVINGS`] times: the largest height found
/// convex and the smallest found not, in that order.
fn edge_of_convexity(mut taken: f64, mut refused: f64, convex: impl Fn(f64) -> bool) -> (f64, f64) {
    for _ in 0..EDGE_HALVINGS {
        let mid = 0.5 * (taken + refused);
        if convex(mid) {
            taken = mid;
        } else {
            refused = mid;
        }
    }
    (taken, refused)
}
