//! A scene's drag-law keys: `[model]` takes every parameter of the core's registry
//! ([`crate::dynamics::drag::REGISTERED`]) by its key (`KEY = VALUE`), with no code
//! here for any one law. serde cannot deny unknown fields and flatten at once, so this map
//! takes the `[model]` keys `ModelSpec` does not name and refuses any that is no registered
//! parameter, with serde's "unknown field" wording.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::dynamics::drag::{DragLaw, DragLawError, REGISTERED};

/// The drag-law parameters a scene gives, by key (absent: the parameter's default).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct DragLawFields(BTreeMap<String, f64>);

impl DragLawFields {
    /// The law these values make, each checked against its range.
    ///
    /// # Errors
    /// A value outside its parameter's range.
    pub fn law(&self) -> Result<DragLaw, DragLawError> {
        self.0
            .iter()
            .try_fold(DragLaw::LINEAR, |law, (key, value)| law.with(key, *value))
    }
}

impl From<&DragLaw> for DragLawFields {
    /// The parameters of `law` that differ from their defaults (a linear law writes none).
    fn from(law: &DragLaw) -> Self {
        DragLawFields(
            law.parameters()
                .filter(|(p, v)| *v != p.default)
                .map(|(p, v)| (p.key.to_string(), v))
                .collect(),
        )
    }
}

impl<'de> Deserialize<'de> for DragLawFields {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer.deserialize_map(FieldsVisitor {
            fields: MODEL_FIELDS,
        })
    }
}

/// The `[model]` fields `ModelSpec` names itself, for the unknown-field message.
const MODEL_FIELDS: &str =
    "`kind`, `alpha_rad`, `alpha_over_critical`, `mass_ratio`, `drag`, `friction`";

/// The drag-law parameters of a `[[replay]]` entry: [`DragLawFields`] whose unknown-field
/// message names the entry's own fields. (The entry flattens them in; serde's
/// `deny_unknown_fields` does not work beside a flattened field, and refused every drag-law key.)
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
#[serde(transparent)]
pub struct ReplayDragLaw(pub DragLawFields);

/// The `[[replay]]` entry's fields, for the unknown-field message.
const REPLAY_FIELDS: &str = "`at`, `alpha_rad`, `mass_ratio`, `drag`, `integrator`, `resumed`";

impl<'de> Deserialize<'de> for ReplayDragLaw {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        deserializer
            .deserialize_map(FieldsVisitor {
                fields: REPLAY_FIELDS,
            })
            .map(ReplayDragLaw)
    }
}

/// Whether `key` is a registered drag law's parameter.
pub(crate) fn is_registered_key(key: &str) -> bool {
    REGISTERED.iter().any(|p| p.key == key)
}

/// The registered drag-law parameters, quoted, for a message: "`drag_exponent`".
pub(crate) fn registered_keys() -> String {
    let laws: Vec<_> = REGISTERED.iter().map(|p| format!("`{}`", p.key)).collect();
    laws.join(", ")
}

struct FieldsVisitor {
    /// The fields of the table the parameters sit in, for the message.
    fields: &'static str,
}

impl<'de> serde::de::Visitor<'de> for FieldsVisitor {
    type Value = DragLawFields;

    fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("drag-law parameters")
    }

    fn visit_map<A: serde::de::MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
        let mut values = BTreeMap::new();
        while let Some(key) = map.next_key::<String>()? {
            if !is_registered_key(&key) {
                return Err(serde::de::Error::custom(format!(
                    "unknown field `{key}`, expected one of {} or a drag-law parameter ({})",
                    self.fields,
                    registered_keys()
                )));
            }
            let value: f64 = map.next_value()?;
            values.insert(key, value);
        }
        Ok(DragLawFields(values))
    }
}
