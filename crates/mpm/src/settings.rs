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
    /// Semi-smooth Newton settings. Default: talus-ssn's, with
    /// `ρ_i = 0.3 / max diag S_i` (the return-mapping scale: particle volumes then do
    /// not change ρ's meaning) and 50 iterations.
    pub solver: Settings,
    /// A step whose solve fails is redone as two halves, at most this many times nested.
    /// Default 4.
    pub max_step_halvings: usize,
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
            solver: Settings {
                rho: Rho::PerPointCompliance { factor: 0.3 },
                max_iterations: 50,
                ..Settings::default()
            },
            max_step_halvings: 4,
            rotate_stress: true,
            predictor: Predictor::Previous,
        }
    }
}
