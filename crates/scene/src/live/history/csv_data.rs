//! The plots' data as CSV: which data sets there are ([`PlotData`]), their files and columns,
//! and [`PlotHistory::csv`], each set's text (the app's "Export plot data", the headless
//! renderer's `--plot-data`).

use super::super::Measured;
use super::{Branch, PlotHistory, health_quantities};

/// One of the plotted data sets, as CSV.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlotData {
    /// 1/T against α: `direction,alpha,inverse_period,mass_ratio` (direction "up" or "down";
    /// the m/m0 the point was measured at).
    AlphaSweep,
    /// Settled ∂Ω crossings against m/m0: `mass_ratio,polar_angle,drag` (the drag law the
    /// crossing was measured under).
    Crossings,
    /// The numerical health against time: `t` and the quantities the model measures.
    Health,
    /// The contact force against time: `t,normal_force,friction_needed` (units of the weight
    /// F; friction_needed is `inf` where N ≤ 0).
    Forces,
    /// The motion against time, as θ(t) and θ̇(θ) or the contact path plot it: a cylinder's
    /// `t,theta,theta_dot` (θ unwrapped), a sphere's `t,contact_theta,contact_phi,angular_speed`
    /// (the contact point's polar angle and azimuth on the body, |ω|).
    Series,
}

impl PlotData {
    /// All five, in file order.
    pub const ALL: [PlotData; 5] = [
        PlotData::AlphaSweep,
        PlotData::Crossings,
        PlotData::Health,
        PlotData::Forces,
        PlotData::Series,
    ];

    /// What its columns are, for [`PlotMeta`](super::plot_meta::PlotMeta).
    pub fn columns(self) -> &'static str {
        match self {
            PlotData::AlphaSweep => {
                "direction (up/down), alpha (rad), inverse_period (1/T; T a cylinder's full turn, a \
                 sphere's whole cycle once decided; 0 where the body halted), \
                 mass_ratio (m/m0 when measured), drag (the drag law when measured)"
            }
            PlotData::Crossings => {
                "mass_ratio, polar_angle of a settled crossing of ∂Ω (rad), drag (the drag law \
                 when measured)"
            }
            PlotData::Health => "t and the worst health quantities so far of the model",
            PlotData::Forces => "t, normal_force (N/F), friction_needed (|f_t|/N)",
            PlotData::Series => {
                "cylinder: t, theta (unwrapped), theta_dot; sphere: t, contact_theta, \
                 contact_phi, angular_speed"
            }
        }
    }

    /// The file name each is written to.
    pub fn file_name(self) -> &'static str {
        match self {
            PlotData::AlphaSweep => "sweep-alpha.csv",
            PlotData::Crossings => "sweep-mass.csv",
            PlotData::Health => "health.csv",
            PlotData::Forces => "contact-force.csv",
            PlotData::Series => "series.csv",
        }
    }
}

impl PlotHistory {
    /// `data` as CSV text (a header and one row per point; numbers in shortest round-trip
    /// form). `measured` picks the health columns.
    pub fn csv(&self, data: PlotData, measured: Measured) -> String {
        let mut out = csv::Writer::from_writer(Vec::new());
        // Shortest round-trip digits with an exponent where short (4.5e-16, not 0.000…045),
        // as `rollphase simulate` writes its CSV.
        let number = |v: f64| ryu::Buffer::new().format(v).to_string();
        // Writing to memory cannot fail.
        let mut row = |fields: Vec<String>| {
            out.write_record(&fields).expect("CSV to memory");
        };
        match data {
            PlotData::AlphaSweep => {
                row(vec![
                    "direction".into(),
                    "alpha".into(),
                    "inverse_period".into(),
                    "mass_ratio".into(),
                    "drag".into(),
                ]);
                for (direction, name) in [(Branch::Up, "up"), (Branch::Down, "down")] {
                    for ([a, f, m], drag) in self.sweep_with_regime(direction) {
                        row(vec![
                            name.into(),
                            number(a),
                            number(f),
                            number(m),
                            drag.into(),
                        ]);
                    }
                }
            }
            PlotData::Crossings => {
                row(vec![
                    "mass_ratio".into(),
                    "polar_angle".into(),
                    "drag".into(),
                ]);
                for ([m, theta], law) in self.crossings.points.iter().zip(&self.crossings.laws) {
                    row(vec![number(*m), number(*theta), law.clone()]);
                }
            }
            PlotData::Health => {
                let columns = health_quantities(measured);
                let mut header = vec!["t".to_string()];
                header.extend(columns.iter().map(|c| c.column.to_string()));
                row(header);
                for s in self.samples() {
                    let mut fields = vec![number(s.t)];
                    fields.extend(columns.iter().map(|c| number((c.value)(s))));
                    row(fields);
                }
            }
            PlotData::Series if measured.quat_norm => {
                row(["t", "contact_theta", "contact_phi", "angular_speed"]
                    .map(String::from)
                    .to_vec());
                for s in self.samples() {
                    row(vec![
                        number(s.t),
                        number(s.theta),
                        number(s.phi),
                        number(s.rate),
                    ]);
                }
            }
            PlotData::Series => {
                row(["t", "theta", "theta_dot"].map(String::from).to_vec());
                for s in self.samples() {
                    row(vec![number(s.t), number(s.theta), number(s.rate)]);
                }
            }
            PlotData::Forces => {
                row(vec![
                    "t".into(),
                    "normal_force".into(),
                    "friction_needed".into(),
                ]);
                for s in self.samples() {
                    row(vec![
                        number(s.t),
                        number(s.normal_force),
                        number(s.friction_needed),
                    ]);
                }
            }
        }
        String::from_utf8(out.into_inner().expect("CSV to memory")).expect("CSV of ASCII")
    }
}
