//! Between steps of a run (or trials of a factor of safety), with the GIL taken back:
//! Python's pending signals (Ctrl-C) and the progress callback. The run stops after the
//! step in progress and writes its files; what stopped it is raised afterwards.
use std::ops::ControlFlow;
use std::sync::{Arc, Mutex};

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use talus::run::{Observer, StepProgress};

use crate::errors::raise;

/// Between steps, with the GIL taken back: Ctrl-C (Python's pending signals) and the
/// callback. What stopped the run is kept to be raised once the run wrote its files.
pub(crate) struct Watch {
    callback: Option<Py<PyAny>>,
    stopped: Mutex<Option<Stop>>,
}

enum Stop {
    /// A signal handler or the callback raised this.
    Raised(PyErr),
    /// The callback returned `False`.
    Asked,
}

impl Watch {
    pub(crate) fn new(callback: Option<Py<PyAny>>) -> Arc<Self> {
        Arc::new(Self {
            callback,
            stopped: Mutex::new(None),
        })
    }

    /// The run loop's observer, calling [`Watch::observe`].
    pub(crate) fn observer(self: &Arc<Self>) -> Observer {
        let watch = Arc::clone(self);
        Arc::new(move |p: &StepProgress| watch.observe(p))
    }

    /// Once the run wrote its files: what stopped it, raised (`report`: what it wrote).
    pub(crate) fn raise_stop(&self, py: Python<'_>, report: &Bound<'_, PyDict>) -> PyResult<()> {
        let stopped = self.stopped.lock().ok().and_then(|mut s| s.take());
        match stopped {
            Some(Stop::Raised(e)) => Err(e),
            Some(Stop::Asked) => {
                let why = "the progress callback returned False".to_string();
                Err(raise(py, "Interrupted", (why, report.clone())))
            }
            None => Ok(()),
        }
    }

    fn observe(&self, p: &StepProgress) -> ControlFlow<()> {
        let stop = Python::attach(|py| {
            if let Err(e) = py.check_signals() {
                return Some(Stop::Raised(e));
            }
            let callback = self.callback.as_ref()?;
            let news = PyDict::new(py);
            let called = news
                .set_item("step", p.step)
                .and_then(|_| news.set_item("steps", p.steps))
                .and_then(|_| news.set_item("time", p.time))
                .and_then(|_| news.set_item("newton_iterations", p.newton_iterations))
                .and_then(|_| news.set_item("substeps", p.substeps))
                .and_then(|_| news.set_item("relative_residual", p.relative_residual))
                .and_then(|_| news.set_item("message", &p.message))
                .and_then(|_| callback.call1(py, (news,)));
            match called {
                Err(e) => Some(Stop::Raised(e)),
                // Only an explicit False stops: a callback returning None goes on.
                Ok(r) if r.bind(py).is(&PyBool::new(py, false)) => Some(Stop::Asked),
                Ok(_) => None,
            }
        });
        match stop {
            None => ControlFlow::Continue(()),
            Some(stop) => {
                if let Ok(mut slot) = self.stopped.lock() {
                    *slot = Some(stop);
                }
                ControlFlow::Break(())
            }
        }
    }
}
