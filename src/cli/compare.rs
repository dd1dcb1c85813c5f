//! `decohesion compare A B`: two run results (summaries, time series or captures) observable
//! by observable ([`crate::compare`]), as a table or JSON, with an exit status for CI.

use crate::compare::{compare_files, Tolerances};
use std::path::Path;

/// Exit status: everything within tolerance.
pub const SAME: i32 = 0;
/// Exit status: some observable moved beyond its tolerance.
pub const MOVED: i32 = 1;
/// Exit status: a file that cannot be compared, or a bad `--tol`.
pub const BAD_INPUT: i32 = 2;

/// Compares `a` and `b`, prints the table (or the JSON with `json`) on standard output and an
/// error on standard error; returns the exit status ([`SAME`], [`MOVED`], [`BAD_INPUT`]).
pub fn compare(a: &Path, b: &Path, tol: &[String], json: bool) -> i32 {
    let report = Tolerances::parse(tol).and_then(|t| compare_files(a, b, &t));
    match report {
        Err(e) => {
            eprintln!("error: {e}");
            BAD_INPUT
        }
        Ok(r) => {
            if json {
                println!("{}", serde_json::to_string_pretty(&r.json()).unwrap());
            } else {
                print!("{}", r.table());
            }
            if r.moved().next().is_some() {
                MOVED
            } else {
                SAME
            }
        }
    }
}
