use talus_ssn::{Rho, Settings};

/// Where each step's Newton iteration starts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Predictor {
    /// The particles' stresses of the last step.
    #[default]
    Previous,
    /// One elastic solve on the step's operator.
    Elastic,
}

/// MPM settings; `MpmSettings::default()` documents the defaults.
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
    /// Semi-smooth Newton settings. Default: talus-ssn's, with
    /// `ρ_i = 0.3 / max diag S_i` (the return-mapping scale: particle volumes then do
    /// not change ρ's meaning) and 50 iterations.
    pub solver: Settings,
    /// A step whose solve fails is redone as two halves, at most this many times nested.
    /// Default 4.
    pub max_step_halvings: usize,
    /// Step-size memory: a step that had to be halved starts the next one at the sub-step
    /// that converged (its failed attempts at the larger size are skipped), and after this
    /// many steps at that size without a halving, tries twice the size again. 0 forgets:
    /// every step starts at the full h. Default 4.
    pub halving_memory: usize,
    /// Rotate each particle's stress with its spin over the step (`σ ← R σ Rᵀ`,
    /// `R = exp(h ω)`), so that a rigid rotation carries the stress with it and the
    /// stress update is objective. Default true.
    pub rotate_stress: bool,
    pub predictor: Predictor,
}

impl Default for MpmSettings {
    fn default() -> Self {
        Self {
            flip_ratio: 0.95,
            flip_reference_time: Some(1e-3),
            solver: Settings {
                rho: Rho::PerPointCompliance { factor: 0.3 },
                max_iterations: 50,
                ..Settings::default()
            },
            max_step_halvings: 4,
            halving_memory: 4,
            rotate_stress: true,
            predictor: Predictor::Previous,
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
