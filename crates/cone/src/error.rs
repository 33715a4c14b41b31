/// Invalid description of a cone or a cylinder.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ConeError {
    /// A parameter is out of its domain; `expected` states the domain.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidParameter {
        name: &'static str,
        value: f64,
        expected: &'static str,
    },
}
