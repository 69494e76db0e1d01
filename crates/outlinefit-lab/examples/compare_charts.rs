//! The three charts `outlinefit compare` draws (convergence, box plot of the totals, minimum
//! error per segment), from a small comparison run through the library: harmony search,
//! the genetic algorithm and particle swarm, five seeded runs each, on the letter `s` of
//! the bundled samples. Not a check (the tests hold the charts' contents); pictures to look
//! at when changing them.
//!
//! `cargo run --release --example compare_charts [-- OUTDIR]` (default: the system's
//! temporary directory); prints the paths written.

use outlinefit::optim::{Algorithm, DEFAULT_SEED};
use outlinefit::Config;
use outlinefit::Search;
use outlinefit_lab::compare::{compare_image, output, CompareOptions, DEFAULT_HISTORY_POINTS};
use std::path::{Path, PathBuf};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = std::env::args()
        .nth(1)
        .map_or_else(std::env::temp_dir, PathBuf::from);
    let image = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../samples/s.png");
    let options = CompareOptions {
        optimizers: vec![Algorithm::Hs, Algorithm::Ga, Algorithm::Pso],
        runs: 5,
        budget: 2000,
        search: Search::Weights,
        seed: DEFAULT_SEED,
        search_box_scale: 1.0,
        history_points: DEFAULT_HISTORY_POINTS,
        trace: Config::default(),
    };
    let comparison = compare_image(&image, &options, &|| {})?;
    for (kind, svg) in output::charts(&comparison)? {
        let path = dir.join(format!("outlinefit-s-{kind}.svg"));
        std::fs::write(&path, svg)?;
        println!("{}", path.display());
    }
    Ok(())
}
