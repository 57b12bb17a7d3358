//! The one place that turns a [`Method`] into its [`Integrator`].

use super::dop853::Dop853;
use super::dopri5::Dopri5;
use super::explicit::ExplicitRk;
use super::integrator::{ErrorWeights, Integrator};
use super::options::{Method, SolverOptions};
use crate::formulation::Formulation;

/// The integrator of `opts.method` for the formulation `f` and error weights `weights`.
pub(crate) fn new_integrator<F: Formulation + ?Sized>(
    opts: &SolverOptions,
    f: &F,
    weights: ErrorWeights,
) -> Box<dyn Integrator<F>> {
    let n = f.n_states();
    let beta = opts.beta_or_default();
    let cut = opts.explicit_rk.cut_at_events;
    match opts.method {
        Method::Dopri5 => Box::new(ExplicitRk::<Dopri5>::new(n, weights, beta, cut)),
        Method::Dop853 => Box::new(ExplicitRk::<Dop853>::new(n, weights, beta, cut)),
        Method::Radau5 => Box::new(super::radau5::Radau5Method::new(
            f,
            &weights,
            opts.h_max,
            &opts.radau5,
        )),
        #[cfg(feature = "ida")]
        Method::Ida => Box::new(
            super::ida::IdaMethod::new(n, weights, opts.h_max)
                .linear_solver(opts.ida.linear_solver),
        ),
    }
}
