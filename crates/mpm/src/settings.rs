/// The transfers' settings; `MpmSettings::default()` documents the defaults. The Newton
/// solve and its step control are the stepping engine's.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MpmSettings {
    /// α of eq. 13, the PIC/FLIP ratio, as the weight of the FLIP velocity:
    /// `v = α v_FLIP + (1 − α) v_PIC` (0 = PIC, 1 = FLIP). Default 0.95, the low end of
    /// the paper's 0.95–0.99. Eq. 13 prints α on the PIC term; with that reading the paper's
    /// range is 95–99% PIC, which damps a granular collapse to 60% of its measured runout
    /// (docs/mpm.md). The MPM literature's 0.95–0.99 is the FLIP weight, as here.
    pub flip_ratio: f64,
    /// The time over which `flip_ratio` applies (s). G2P keeps the fraction α of the
    /// particle velocity the grid does not carry, so that fraction decays as `α^(t/h)`: a
    /// damping per step, whose rate per second grows as h shrinks and vanishes as h grows
    /// (docs/mpm.md, "The PIC/FLIP blend is a damping per unit time"). With
    /// `Some(t_ref)` a step of h uses `α^(h / t_ref)` ([`MpmSettings::flip_weight`]):
    /// the same decay `α^(t / t_ref)` over the same time whatever the step. `None`: α per
    /// step, as eq. 13 prints it. Default `Some(1e-3)`, the step of the column scenes,
    /// at which both readings agree.
    pub flip_reference_time: Option<f64>,
    /// Rotate each particle's stress with its spin over the step (`σ ← R σ Rᵀ`,
    /// `R = exp(h ω)`), so that a rigid rotation carries the stress with it and the
    /// stress update is objective. Default true.
    pub rotate_stress: bool,
    /// Start each sub-step's friction walls from the stick/slide states the last stresses
    /// predict ([`crate::Substep`]; `docs/mpm-performance.md`, 'The matched column') instead
    /// of every node stuck. The passes settle the states to the same tolerance either way;
    /// the prediction saves the passes (and their Newton iterations) that a flowing body
    /// spends leaving the all-stuck start. Default true.
    pub contact_predictor: bool,
}

impl Default for MpmSettings {
    fn default() -> Self {
        Self {
            flip_ratio: 0.95,
            flip_reference_time: Some(1e-3),
            rotate_stress: true,
            contact_predictor: true,
        }
    }
}

impl MpmSettings {
    /// The FLIP weight of eq. 13 for a step of `h` (s): `α^(h / t_ref)`, or `α` without a
    /// reference time.
    pub fn flip_weight(&self, h: f64) -> f64 {
        match self.flip_reference_time {
            Some(t_ref) => self.flip_ratio.powf(h / t_ref),
            None => self.flip_ratio,
        }
    }
}
