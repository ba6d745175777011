//! The model's parts on the command line, from the core's registries: the drag-law flags, one
//! per parameter in [`crate::dynamics::drag::REGISTERED`] (so a new law gets its flag, its
//! `--help` line and its range check without code here), and the list of the models in
//! [`crate::dynamics::models::REGISTERED`] at the end of `--help`. `simulate`, `period` and
//! `predict` flatten it in.

use anyhow::{Result, anyhow};
use clap::{Arg, ArgMatches, Args, Command, FromArgMatches};

use crate::dynamics::drag::{DragLaw, REGISTERED};

/// The values given for registered drag-law parameters (absent: the parameter's default).
#[derive(Debug, Clone, Default)]
pub struct DragLawArgs {
    given: Vec<(&'static str, &'static str, f64)>,
}

impl DragLawArgs {
    /// The law the flags ask for, each value checked against its parameter's range; the
    /// error names the flag.
    pub fn law(&self) -> Result<DragLaw> {
        self.given
            .iter()
            .try_fold(DragLaw::LINEAR, |law, &(key, flag, value)| {
                law.with(key, value).map_err(|e| anyhow!("--{flag}: {e}"))
            })
    }
}

/// The parameters of `law` away from their defaults, as `, KEY = VALUE` for a command's
/// header line; empty for the paper's linear drag.
pub fn describe(law: &DragLaw) -> String {
    law.parameters()
        .filter(|(p, v)| *v != p.default)
        .map(|(p, v)| format!(", {} = {v}", p.key))
        .collect()
}

impl FromArgMatches for DragLawArgs {
    fn from_arg_matches(matches: &ArgMatches) -> Result<Self, clap::Error> {
        let given = REGISTERED
            .iter()
            .filter_map(|p| matches.get_one::<f64>(p.key).map(|v| (p.key, p.flag, *v)))
            .collect();
        Ok(Self { given })
    }

    fn update_from_arg_matches(&mut self, matches: &ArgMatches) -> Result<(), clap::Error> {
        *self = Self::from_arg_matches(matches)?;
        Ok(())
    }
}

impl Args for DragLawArgs {
    fn augment_args(cmd: Command) -> Command {
        let cmd = cmd.after_long_help(format!(
            "Models (the body's dimension and --mass choose one; its name is the one every \
             summary, CSV and JSON uses):\n{}",
            crate::dynamics::models::listing()
                .lines()
                .map(|l| format!("  {l}"))
                .collect::<Vec<_>>()
                .join("\n")
        ));
        REGISTERED.iter().fold(cmd, |cmd, p| {
            cmd.arg(
                Arg::new(p.key)
                    .long(p.flag)
                    .value_name("VALUE")
                    .value_parser(clap::value_parser!(f64))
                    .allow_negative_numbers(true)
                    .help(format!("{} [default: {}]", p.help, p.default)),
            )
        })
    }

    fn augment_args_for_update(cmd: Command) -> Command {
        Self::augment_args(cmd)
    }
}
