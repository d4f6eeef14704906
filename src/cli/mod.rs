//! Subcommand handlers: each turns parsed arguments into library calls and prints the result.

pub mod bench;
pub mod fit_indentation;
pub mod homogenize;
pub mod merge;
pub mod run;
pub mod theory;
pub mod theory_law;

/// Largest count of points or samples a command accepts (`turf theory curve --points`,
/// `turf theory indentation-law --samples`, `turf homogenize --samples`): 10⁷ rows are
/// hundreds of MB of CSV, far beyond any plot or fit, and a bound keeps a typo from
/// exhausting memory.
pub const MAX_POINTS: usize = 10_000_000;

/// Refuse a count given to `--flag` outside `min..=MAX_POINTS`.
pub fn bounded_count(flag: &str, n: usize, min: usize) -> anyhow::Result<usize> {
    if n < min || n > MAX_POINTS {
        anyhow::bail!("--{flag} {n} is not allowed: must lie in {min}..={MAX_POINTS}");
    }
    Ok(n)
}
