//! [`FieldCache`]: the Poincaré field of a scene's body and ramp (see
//! [`crate::analysis::orbits::poincare_field::poincare_field`]), computed once per (body, α, resolution)
//! on a worker thread for the app, or on the caller's thread for headless frames. The view only
//! draws the arrows it gets from here.

use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use crate::analysis::orbits::poincare_field::{FieldArrow, poincare_field};
use crate::dynamics::Ramp;
use crate::geometry::Body;
use crate::scene::SceneSetup;

/// Key of a cached field: the body's shape file text, α's bits, the arrow count and rtol's bits.
type FieldKey = (String, u64, usize, u64);

/// Poincaré fields computed once per (body, α, resolution), on a worker thread.
#[derive(Default, Clone)]
pub struct FieldCache {
    entries: Arc<Mutex<HashMap<FieldKey, FieldEntry>>>,
}

#[derive(Clone)]
enum FieldEntry {
    Computing,
    Ready(Arc<Vec<FieldArrow>>),
    Failed(String),
}

impl FieldCache {
    fn key(setup: &SceneSetup, ramp: &Ramp) -> FieldKey {
        let p = &setup.scene.poincare;
        (
            // The key only tells bodies apart; a body JSON cannot refuse is keyed by its Debug.
            setup
                .body
                .to_shape()
                .to_json()
                .unwrap_or_else(|_| format!("{:?}", setup.body.to_shape())),
            ramp.alpha_rad.to_bits(),
            p.arrows,
            p.rtol.to_bits(),
        )
    }

    /// The field if it is ready; otherwise starts computing it on a worker thread (once) and
    /// returns `Ok(None)`. A failed computation is reported once per key.
    pub fn request(
        &self,
        setup: &SceneSetup,
        ramp: &Ramp,
    ) -> Result<Option<Arc<Vec<FieldArrow>>>, String> {
        let key = Self::key(setup, ramp);
        let mut entries = self.entries.lock().map_err(|e| e.to_string())?;
        match entries.get(&key) {
            Some(FieldEntry::Ready(f)) => return Ok(Some(f.clone())),
            Some(FieldEntry::Computing) => return Ok(None),
            Some(FieldEntry::Failed(e)) => return Err(e.clone()),
            None => {}
        }
        entries.insert(key.clone(), FieldEntry::Computing);
        drop(entries);
        let cache = self.entries.clone();
        let (setup, ramp) = (setup.clone(), *ramp);
        let failed_key = key.clone();
        let started = std::thread::Builder::new()
            .name("poincare field".into())
            .spawn(move || {
                let result = compute_field(&setup, &ramp);
                if let Ok(mut entries) = cache.lock() {
                    entries.insert(
                        key,
                        match result {
                            Ok(f) => FieldEntry::Ready(Arc::new(f)),
                            Err(e) => FieldEntry::Failed(e),
                        },
                    );
                }
            });
        if let Err(e) = started {
            let message = format!("cannot start the Poincaré field's thread: {e}");
            if let Ok(mut entries) = self.entries.lock() {
                entries.insert(failed_key, FieldEntry::Failed(message.clone()));
            }
            return Err(message);
        }
        Ok(None)
    }

    /// The field, computed now if it is not cached (headless: frames must not depend on timing).
    pub fn get_blocking(
        &self,
        setup: &SceneSetup,
        ramp: &Ramp,
    ) -> Result<Arc<Vec<FieldArrow>>, String> {
        let key = Self::key(setup, ramp);
        if let Ok(entries) = self.entries.lock()
            && let Some(FieldEntry::Ready(f)) = entries.get(&key)
        {
            return Ok(f.clone());
        }
        let f = Arc::new(compute_field(setup, ramp)?);
        if let Ok(mut entries) = self.entries.lock() {
            entries.insert(key, FieldEntry::Ready(f.clone()));
        }
        Ok(f)
    }
}

fn compute_field(setup: &SceneSetup, ramp: &Ramp) -> Result<Vec<FieldArrow>, String> {
    let Body::Sphere(s) = &setup.body else {
        return Err("the Poincaré field needs a 3D body".into());
    };
    let p = &setup.scene.poincare;
    poincare_field(s, ramp, p.arrows, p.t_max, p.rtol, &|| {}).map_err(|e| e.to_string())
}
