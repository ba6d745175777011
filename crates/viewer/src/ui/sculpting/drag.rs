//! A sculpting drag: from a press on the body, the pointer's height above or below the press is
//! the stroke's height (up pulls the surface out, down presses it in). Every move sculpts the
//! body as it was at the press again and restarts the run from the press's contact, so the
//! readout follows live, moving back takes the stroke back, and the release keeps one stroke
//! (one undo). A drag past the edge of convexity stops at the edge, found by halving, and says
//! why.

use super::super::{AppUi, UiAction};
use super::contact_now;
use crate::geometry::Body;
use crate::geometry::sculpt::{MAX_STROKE_HEIGHT, SculptError, Stroke, StrokePoint, sculpt};
use crate::live::SimStatus;
use crate::scene::InitialSpec;
use crate::view::pick::body_point_at;

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

/// A stroke being dragged: where it was pressed, what the body was then, and the height it has
/// now. Every move sculpts the body before the drag again, so the drag is one stroke.
pub(super) struct DragStroke {
    at: StrokePoint,
    /// The press's height on the screen (points): the height follows the pointer from there.
    origin_y: f32,
    /// The body before the drag.
    base: Body,
    /// α* before the drag.
    base_alpha_star: f64,
    /// The contact every restart starts from: the run's at the press.
    initial: InitialSpec,
    /// The height the running body has (0: the body before the drag).
    pub(super) height: f64,
    /// Once a height was refused: the largest height of that sign taken, the smallest refused,
    /// and why (heights past it are not tried again: the base does not change during a drag).
    edge: Option<(f64, f64, String)>,
}

impl AppUi {
    /// A press at frame pixel (`x`, `y`) of the scene area that became a drag while sculpting,
    /// pressed at `origin_y` (screen points): the drag sculpts if the body is under the press.
    /// Returns whether it does (otherwise the drag turns the camera, as without sculpting).
    pub(in crate::ui) fn sculpt_drag_start(
        &mut self,
        (x, y): (f32, f32),
        origin_y: f32,
        status: &SimStatus,
    ) -> bool {
        let Some(view) = self.sculpt.pick_view else {
            return false;
        };
        let Some(at) = body_point_at(&view, &status.setup.body, x, y) else {
            return false;
        };
        if let Err(e) = status.setup.body.check_convex() {
            self.notice = Some((
                format!(
                    "this body is not strictly convex ({e}): it rolls on its hull, and a stroke \
                     keeps it so; sculpt a convex body"
                ),
                true,
            ));
            return true;
        }
        let Some(session) = self.sculpt.session.as_ref() else {
            return false;
        };
        self.sculpt.dragging = Some(DragStroke {
            at,
            origin_y,
            base: session.body().clone(),
            base_alpha_star: status.setup.alpha_star,
            initial: contact_now(status),
            height: 0.0,
            edge: None,
        });
        self.notice = Some((
            "drag up to pull the surface out, down to press it in; release to keep".into(),
            false,
        ));
        true
    }

    /// The pointer of a sculpting drag is at height `y` (screen points): the body before the drag
    /// with the stroke of that height, run from the press's contact, unless the height moved by
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
        let height = match &drag.edge {
            // Past the edge found before: the edge.
            Some((taken, refused, _))
                if wanted * refused > 0.0 && wanted.abs() >= refused.abs() =>
            {
                *taken
            }
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
                        let said = (drag.height, drag.edge.clone());
                        self.say_drag(said.0, None, said.1.map(|(_, r, w)| (r, w)));
                        return;
                    }
                }
            }
            Err(e) => {
                self.notice = Some((e.to_string(), true));
                return;
            }
        };
        let at_edge = drag
            .edge
            .as_ref()
            .filter(|(taken, ..)| *taken == height && height != 0.0)
            .map(|(_, refused, why)| (*refused, why.clone()));
        let was = std::mem::replace(&mut drag.height, height);
        let (base_alpha_star, initial) = (drag.base_alpha_star, drag.initial.clone());
        let Some(session) = self.sculpt.session.as_mut() else {
            return;
        };
        if was != 0.0 {
            session.drop_newest();
        }
        if height != 0.0
            && let Err(e) = session.set_body(body.clone())
        {
            self.notice = Some((e.to_string(), true));
            return;
        }
        self.sculpt.in_flight.push(body.to_shape());
        let now = self.run_sculpted(&body, "", Some(initial), status, actions);
        self.say_drag(height, now.map(|a| (base_alpha_star, a)), at_edge);
    }

    /// The notice while a drag sculpts: the height, α* before and now, and the edge if the drag
    /// went past it.
    fn say_drag(
        &mut self,
        height: f64,
        alpha_stars: Option<(f64, f64)>,
        edge: Option<(f64, String)>,
    ) {
        let what = if height > 0.0 {
            format!("pulling a bump out by {height:.4}")
        } else if height < 0.0 {
            format!("pressing a dent in by {:.4}", -height)
        } else {
            "back to the body before the drag".into()
        };
        let alpha = alpha_stars.map_or(String::new(), |(a, b)| format!("; α* {a:.5} → {b:.5} rad"));
        match edge {
            Some((refused, why)) => {
                self.notice = Some((
                    format!(
                        "{what} mean r{alpha}: the edge — a height of {refused:.4} would leave \
                         the body not strictly convex ({why}); release to keep"
                    ),
                    true,
                ))
            }
            None => self.notice = Some((format!("{what} mean r{alpha}; release to keep"), false)),
        }
    }

    /// The release of a sculpting drag: the body it made is kept as one stroke (one undo), or
    /// nothing changed if it ended where it began.
    pub(in crate::ui) fn sculpt_drag_end(&mut self) {
        let Some(drag) = self.sculpt.dragging.take() else {
            return;
        };
        let h = drag.height;
        self.notice = Some((
            match (h, &drag.edge) {
                (0.0, _) => "the drag ended where it began: the body is as before".into(),
                (_, Some((taken, _, why))) if *taken == h => format!(
                    "{} by {:.4} mean r, at the edge of convexity ({why}); Ctrl+Z undoes",
                    if h > 0.0 {
                        "pulled a bump"
                    } else {
                        "pressed a dent"
                    },
                    h.abs()
                ),
                _ => format!(
                    "{} by {:.4} mean r; Ctrl+Z undoes",
                    if h > 0.0 {
                        "pulled a bump"
                    } else {
                        "pressed a dent"
                    },
                    h.abs()
                ),
            },
            false,
        ));
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
