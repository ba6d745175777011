//! The fast / balanced / precise presets deliver the errors they advertise: re-measured on the
//! four models and bundled bodies against the converged reference, each preset's worst error is
//! within its documented bound, and the bound is not vacuous (within 20× of what is measured).

use rollphase::analysis::accuracy::trajectories::{self, REFERENCE};
use rollphase::assets::{
    DISK as BUNDLED_DISK, DISK_INERTIAL as BUNDLED_DISK_INERTIAL, SPHERE as BUNDLED_SPHERE,
};
use rollphase::geometry::{Body, ShapeFile};
use rollphase::integrate::Preset;

fn body(text: &str) -> Body {
    Body::from_shape(&ShapeFile::from_json(text).unwrap()).unwrap()
}

#[test]
fn presets_meet_their_documented_errors() {
    let cases = trajectories::default_cases(
        &body(BUNDLED_DISK),
        &body(BUNDLED_DISK_INERTIAL),
        &body(BUNDLED_SPHERE),
    );
    let refs: Vec<_> = cases
        .iter()
        .map(|c| trajectories::run_case(c, REFERENCE).unwrap())
        .collect();
    for preset in Preset::ALL {
        let (mut worst_state, mut worst_period) = (0.0f64, 0.0f64);
        for (case, reference) in cases.iter().zip(&refs) {
            let run = trajectories::run_case(case, preset.method());
            let row = trajectories::row(case, preset.method(), &run, reference);
            assert!(
                row.failure.is_none(),
                "{} {}: {:?}",
                preset.name(),
                case.model(),
                row.failure
            );
            assert!(
                row.period_error.is_finite(),
                "{}: the period is measurable",
                case.model()
            );
            worst_state = worst_state.max(row.state_error);
            worst_period = worst_period.max(row.period_error);
        }
        let (es, ep) = (
            preset.expected_state_error(),
            preset.expected_period_error(),
        );
        assert!(
            worst_state <= es && worst_state >= es / 20.0,
            "{}: state error {worst_state:e} vs documented {es:e}",
            preset.name()
        );
        assert!(
            worst_period <= ep && worst_period >= ep / 20.0,
            "{}: period error {worst_period:e} vs documented {ep:e}",
            preset.name()
        );
    }
}
