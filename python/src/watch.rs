//! Between steps of a run (or trials of a factor of safety), with the GIL taken back:
//! Python's pending signals (Ctrl-C) and the progress callback. The run stops after the
//! step in progress and writes its files; what stopped it is raised afterwards.
use std::ops::ControlFlow;
use std::sync::{Arc, Mutex};
use std::time::Duration;

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict};
use talus::run::{Observer, StepProgress};

use crate::errors::raise;

/// How often the calling thread checks Python's signals while a worker steps.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

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

    /// `work`, the GIL released, on a worker of rayon's pool (`talus_ssn::on_pool`: the
    /// Newton iteration's parallel regions fork from there at a fraction of the cost). This
    /// thread checks Python's signals meanwhile, since CPython runs their handlers on the
    /// main thread only: a Ctrl-C is kept and stops the run after the step in progress.
    pub(crate) fn detach_on_pool<R: Send>(
        &self,
        py: Python<'_>,
        work: impl FnOnce() -> R + Send,
    ) -> R {
        py.detach(|| {
            talus_ssn::on_pool_polling(work, SIGNAL_POLL, || {
                if let Err(e) = Python::attach(|py| py.check_signals()) {
                    self.keep(Stop::Raised(e));
                }
            })
        })
    }

    /// The first reason to stop is the one raised.
    fn keep(&self, stop: Stop) {
        if let Ok(mut slot) = self.stopped.lock() {
            slot.get_or_insert(stop);
        }
    }

    fn observe(&self, p: &StepProgress) -> ControlFlow<()> {
        // A signal the calling thread kept while this step ran.
        if self.stopped.lock().is_ok_and(|s| s.is_some()) {
            return ControlFlow::Break(());
        }
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
                Ok(r) if r.bind(py).is(PyBool::new(py, false)) => Some(Stop::Asked),
                Ok(_) => None,
            }
        });
        match stop {
            None => ControlFlow::Continue(()),
            Some(stop) => {
                self.keep(stop);
                ControlFlow::Break(())
            }
        }
    }
}
