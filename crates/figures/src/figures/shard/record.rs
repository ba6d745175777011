//! A job's result as numbers, for shard files: [`Record`] encodes and decodes it
//! (`decode(encode(x)) == x` bit for bit), and its `decode` refuses any value the figure's
//! reduction could not handle (an index, a count, a NaN where a number is needed).

use anyhow::{Result, anyhow, bail};
use glam::DVec3;

use crate::analysis::orbits::sphere_orbits::{Crossing, Settlement};
use crate::dynamics::validity::ContactReport;

/// The largest period multiplicity a shard's fate may hold (a sweep's `max_multiplicity` is
/// capped at it).
pub const MAX_FATE_MULTIPLICITY: usize = 64;

/// The numbers of one record, read in order by [`Record::decode`].
pub struct Fields<'a>(std::slice::Iter<'a, f64>);

impl<'a> Fields<'a> {
    /// The numbers of `record`.
    pub fn of(record: &'a [f64]) -> Self {
        Fields(record.iter())
    }

    /// How many numbers are left unread (a record that decodes with some left is refused).
    pub fn remaining(&self) -> usize {
        self.0.len()
    }

    /// The next number.
    pub fn number(&mut self) -> Result<f64> {
        self.0
            .next()
            .copied()
            .ok_or_else(|| anyhow!("the record ends early"))
    }

    /// The next number as a count or index (a whole number ≥ 0).
    pub fn count(&mut self) -> Result<usize> {
        let v = self.number()?;
        if v >= 0.0 && v.fract() == 0.0 && v < 9.0e15 {
            Ok(v as usize)
        } else {
            bail!("{v} is not a count")
        }
    }
}

/// A job's result as numbers, for shard files: `decode(encode(x)) == x` bit for bit.
pub trait Record: Sized {
    /// Appends this result's numbers.
    fn encode(&self, out: &mut Vec<f64>);
    /// Reads a result back.
    fn decode(fields: &mut Fields) -> Result<Self>;
}

impl Record for f64 {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(*self);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        f.number()
    }
}

impl Record for usize {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(*self as f64);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        f.count()
    }
}

impl Record for u64 {
    // Two 32-bit halves: a seed may exceed 2^53, where f64 stops holding every integer.
    fn encode(&self, out: &mut Vec<f64>) {
        out.extend([(*self >> 32) as f64, (*self & 0xffff_ffff) as f64]);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let (hi, lo) = (f.count()?, f.count()?);
        if hi > u32::MAX as usize || lo > u32::MAX as usize {
            bail!("{hi}, {lo} are not the halves of a 64-bit number");
        }
        Ok(((hi as u64) << 32) | lo as u64)
    }
}

impl Record for bool {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(if *self { 1.0 } else { 0.0 });
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        match f.count()? {
            0 => Ok(false),
            1 => Ok(true),
            v => bail!("{v} is not a flag (0 or 1)"),
        }
    }
}

impl Record for DVec3 {
    fn encode(&self, out: &mut Vec<f64>) {
        out.extend(self.to_array());
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(DVec3::new(f.number()?, f.number()?, f.number()?))
    }
}

impl<A: Record, B: Record> Record for (A, B) {
    fn encode(&self, out: &mut Vec<f64>) {
        self.0.encode(out);
        self.1.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok((A::decode(f)?, B::decode(f)?))
    }
}

impl<A: Record, B: Record, C: Record> Record for (A, B, C) {
    fn encode(&self, out: &mut Vec<f64>) {
        self.0.encode(out);
        self.1.encode(out);
        self.2.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok((A::decode(f)?, B::decode(f)?, C::decode(f)?))
    }
}

impl<T: Record> Record for Option<T> {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            None => out.push(0.0),
            Some(v) => {
                out.push(1.0);
                v.encode(out);
            }
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        Ok(if bool::decode(f)? {
            Some(T::decode(f)?)
        } else {
            None
        })
    }
}

impl<T: Record> Record for Vec<T> {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(self.len() as f64);
        for v in self {
            v.encode(out);
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let n = f.count()?;
        // The length comes from a file: grow as items actually arrive.
        let mut v = Vec::with_capacity(n.min(1 << 16));
        for _ in 0..n {
            v.push(T::decode(f)?);
        }
        Ok(v)
    }
}

impl Record for Crossing {
    fn encode(&self, out: &mut Vec<f64>) {
        out.push(self.t);
        out.extend(self.point);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let c = Crossing {
            t: f.number()?,
            point: [f.number()?, f.number()?, f.number()?],
        };
        if !(c.t.is_finite() && c.point.iter().all(|x| x.is_finite())) {
            bail!("a crossing of ∂Ω at t = {} holds a non-finite number", c.t);
        }
        Ok(c)
    }
}

impl Record for ContactReport {
    fn encode(&self, out: &mut Vec<f64>) {
        out.extend([
            self.min_normal_force,
            self.max_normal_force,
            self.max_friction_needed,
        ]);
        self.lift_off_t.encode(out);
        self.slip_t.encode(out);
        self.friction.encode(out);
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let r = ContactReport {
            min_normal_force: f.number()?,
            max_normal_force: f.number()?,
            max_friction_needed: f.number()?,
            lift_off_t: Option::decode(f)?,
            slip_t: Option::decode(f)?,
            friction: Option::decode(f)?,
        };
        // What the reductions rely on: finite forces in order, a friction needed ≥ 0 (infinite
        // once the body left the ramp), times and μ finite and ≥ 0.
        if !(r.min_normal_force.is_finite()
            && r.max_normal_force.is_finite()
            && r.min_normal_force <= r.max_normal_force)
        {
            bail!(
                "normal forces {} … {} are not finite and in order",
                r.min_normal_force,
                r.max_normal_force
            );
        }
        if r.max_friction_needed.is_nan() || r.max_friction_needed < 0.0 {
            bail!("friction needed {} is not ≥ 0", r.max_friction_needed);
        }
        for v in [r.lift_off_t, r.slip_t, r.friction].into_iter().flatten() {
            if !(v.is_finite() && v >= 0.0) {
                bail!("{v} is not a finite time or coefficient ≥ 0");
            }
        }
        Ok(r)
    }
}

impl Record for Settlement {
    fn encode(&self, out: &mut Vec<f64>) {
        match self {
            Settlement::Halts { t } => out.extend([0.0, *t]),
            Settlement::Periodic {
                period,
                k,
                point,
                t,
            } => {
                out.extend([1.0, *period, *k as f64]);
                out.extend(point);
                out.push(*t);
            }
            Settlement::Undecided { omega_end } => out.extend([2.0, *omega_end]),
        }
    }
    fn decode(f: &mut Fields) -> Result<Self> {
        let fate = match f.count()? {
            0 => Settlement::Halts { t: f.number()? },
            1 => Settlement::Periodic {
                period: f.number()?,
                k: f.count()?,
                point: [f.number()?, f.number()?, f.number()?],
                t: f.number()?,
            },
            2 => Settlement::Undecided {
                omega_end: f.number()?,
            },
            v => bail!("{v} is not a fate (0 halts, 1 periodic, 2 undecided)"),
        };
        // The ranges every reduction relies on: times ≥ 0, a period > 0 of 1 to
        // MAX_FATE_MULTIPLICITY crossings, finite points.
        match fate {
            Settlement::Halts { t } if !(t.is_finite() && t >= 0.0) => {
                bail!("halt time {t} is not a finite time ≥ 0")
            }
            Settlement::Periodic {
                period,
                k,
                point,
                t,
            } => {
                if !(period.is_finite() && period > 0.0) {
                    bail!("period {period} is not a finite time > 0");
                }
                if !(1..=MAX_FATE_MULTIPLICITY).contains(&k) {
                    bail!("period multiplicity {k} is not 1 to {MAX_FATE_MULTIPLICITY}");
                }
                if !(t.is_finite() && point.iter().all(|x| x.is_finite())) {
                    bail!("the orbit's point or time is not finite");
                }
            }
            Settlement::Undecided { omega_end } if !(omega_end.is_finite() && omega_end >= 0.0) => {
                bail!("final |ω| {omega_end} is not a finite number ≥ 0")
            }
            _ => {}
        }
        Ok(fate)
    }
}
