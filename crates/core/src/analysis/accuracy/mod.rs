//! The price of accuracy: what each integrator setting costs and what it gets right.
//!
//! | file | what it owns |
//! |---|---|
//! | [`trajectories`] | each model run with each setting against a converged reference: state and energy errors, cost |
//! | [`answers`] | the same settings judged on the answers: fates, multiplicities, periods and orbit counts |

pub mod answers;
pub mod trajectories;
