//! Fuzz target: any bytes handed to the shape-file path (`rollphase inspect FILE`) must give a
//! body or an error, never a panic: parse, validate, and for a valid body compute curvature and
//! the critical angle, exactly as `inspect` does.
#![no_main]

use libfuzzer_sys::fuzz_target;
use rollphase::analysis::critical_angle;
use rollphase::geometry::{Body, ShapeFile};

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let Ok(file) = ShapeFile::from_json(text) else { return };
    let Ok(body) = Body::from_shape(&file) else { return };
    let report = body.curvature();
    let angle = critical_angle(&body);
    // The numbers a user sees must not be NaN for a validated body.
    assert!(!report.curvature_min.is_nan() && !angle.alpha_star.is_nan());
});
