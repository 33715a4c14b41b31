pub mod mpm_run;
pub mod output;
pub mod run;
pub mod run_loop;
pub mod run_results;
pub mod scene;
pub mod simulation;
pub mod verification;
