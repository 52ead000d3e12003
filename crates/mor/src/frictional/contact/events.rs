//! Where a stretch of the contact ends: a stick–slip switch or the end of the contact,
//! located on the dense output of the step in which the stages saw it.

use super::{Eval, Found, Mode, Stretch};
use crate::SolveError;
use crate::dop853::{Dense, Dop853};
use crate::frictional::{failure, first_crossing};

impl<const M: usize> Stretch<'_, M> {
    /// The first event inside the last accepted step: the end of the contact or a switch
    /// (also one there and back within the step, seen at a stage).
    pub(super) fn event_in_step(
        &self,
        solver: &mut Dop853<'_, Self, M>,
    ) -> Result<Option<Found<M>>, SolveError> {
        // The stages' minima include the step's end (evaluated last, for the next step).
        let (c, mode) = (self.contact, self.mode.get());
        let ends = self.low_end.get() <= 0.0;
        let free = matches!(mode, Mode::Tail | Mode::Head);
        let switches = !free && self.low.get() < 0.0;
        if !ends && !switches {
            return Ok(None);
        }
        let e_b = c.eval::<false, M>(solver.y(), mode);
        let dense = solver.dense().map_err(failure)?;
        // The dense output's stages are evaluated last now: the step's end is e_b.
        self.last.set((e_b.f_n, e_b.growth));
        let (x_a, y_a) = solver.last_start();
        let span = (x_a, *y_a, solver.t(), e_b);
        let x_end = if ends {
            // Only a fall of ξ ends the contact (F_n is zero at touch too).
            self.root(&dense, &span, |e| {
                if e.rate < 0.0 {
                    e.end
                } else {
                    e.end.abs().max(f64::MIN_POSITIVE)
                }
            })
        } else {
            None
        };
        let x_switch = if switches {
            self.root(&dense, &span, |e| e.mode)
        } else {
            None
        };
        Ok(match (x_end, x_switch) {
            (Some(x_e), Some(x_s)) if x_s < x_e => Some(Found::Switch(x_s, dense.eval(x_s))),
            (Some(x_e), _) => Some(Found::End(dense.eval(x_e))),
            (None, Some(x_s)) => Some(Found::Switch(x_s, dense.eval(x_s))),
            (None, None) => None,
        })
    }

    /// The first zero crossing from above of `g` on the step (x_a, y_a) to (x_b, e_b)
    /// ([`first_crossing`] on its dense output).
    fn root(
        &self,
        dense: &Dense<M>,
        &(x_a, y_a, x_b, ref e_b): &(f64, [f64; M], f64, Eval<M>),
        g: impl Fn(&Eval<M>) -> f64,
    ) -> Option<f64> {
        let (c, mode) = (self.contact, self.mode.get());
        let value = |x: f64| g(&c.eval::<false, M>(&dense.eval(x), mode));
        let g_a = g(&c.eval::<false, M>(&y_a, mode));
        first_crossing(value, (x_a, g_a), (x_b, g(e_b)))
    }
}
