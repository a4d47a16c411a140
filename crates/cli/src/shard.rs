//! `geardyn plan`, `geardyn run-shard`, `geardyn status`, `geardyn merge`: a grid-shaped command
//! split into shards over a Zarr store (`geardyn_exec::shard`; docs/distributed.md). The plan takes
//! the command's own arguments, turned into its request by the command's own code.

use crate::bifurcation::BifurcationArgs;
use crate::global::MapArgs;
use anyhow::Result;
use clap::{Args, Subcommand};
use geardyn_exec::request::Request;
use geardyn_exec::shard;
use std::path::PathBuf;

/// Arguments of `geardyn plan`.
#[derive(Args, Debug)]
pub struct PlanArgs {
    #[command(subcommand)]
    command: PlanCommand,
}

/// The commands a plan can split.
#[derive(Subcommand, Debug)]
enum PlanCommand {
    /// A two-parameter map: `geardyn plan map2d <map2d arguments> --shards N --out STORE`
    /// (one shard is a block of cells, whole rows when the count allows).
    #[command(allow_negative_numbers = true)]
    Map2d {
        #[command(flatten)]
        args: MapArgs,
        #[command(flatten)]
        shards: Shards,
    },
    /// A bifurcation diagram, mode fixed or multi: `geardyn plan bifurcation <bifurcation
    /// arguments> --shards N --out STORE` (one shard is a run of values, every initial state of
    /// each).
    #[command(allow_negative_numbers = true)]
    Bifurcation {
        #[command(flatten)]
        args: BifurcationArgs,
        #[command(flatten)]
        shards: Shards,
    },
}

/// The shard count of a plan.
#[derive(Args, Debug)]
struct Shards {
    /// Number of shards, at most the grid's points (one chunk of the store's arrays each when the
    /// grid's shape allows a regular chunking into N, else runs of single-row or single-cell
    /// chunks).
    #[arg(long)]
    shards: usize,
}

pub fn plan(a: PlanArgs) -> Result<()> {
    let (request, store, n) = match a.command {
        PlanCommand::Map2d { args, shards } => (
            Request::Map2d(args.request()?.0),
            args.out.clone(),
            shards.shards,
        ),
        PlanCommand::Bifurcation { args, shards } => (
            Request::Bifurcation(args.request()?.0),
            args.out.clone(),
            shards.shards,
        ),
    };
    let command = request.command();
    let p = shard::plan(&store, request, n)?;
    if p.existed {
        println!(
            "{} holds this plan already: {} shards, {} done",
            store.display(),
            p.shards,
            p.done
        );
    } else {
        println!(
            "planned {command} in {} shards -> {} (run: geardyn run-shard {} --shard I, I in 0..={}, or a Slurm array --array=0-{})",
            p.shards,
            store.display(),
            store.display(),
            p.shards - 1,
            p.shards - 1
        );
    }
    Ok(())
}

/// Arguments of `geardyn run-shard`.
#[derive(Args, Debug)]
pub struct RunShardArgs {
    /// The plan's store (made by `geardyn plan`).
    store: PathBuf,
    /// Shard index (default: the Slurm array index, SLURM_ARRAY_TASK_ID).
    #[arg(long)]
    shard: Option<usize>,
}

pub fn run_shard(a: RunShardArgs) -> Result<()> {
    let i = shard::shard_index(a.shard)?;
    let t = std::time::Instant::now();
    let r = shard::run_shard(&a.store, i)?;
    if r.already {
        println!(
            "shard {i} of {} is done already (nothing computed)",
            a.store.display()
        );
    } else {
        println!(
            "shard {i}: {} points in {:.2} s -> {}",
            r.points,
            t.elapsed().as_secs_f64(),
            a.store.display()
        );
    }
    Ok(())
}

/// Arguments of `geardyn status`.
#[derive(Args, Debug)]
pub struct StatusArgs {
    /// The plan's store.
    store: PathBuf,
    /// Print only the missing shards, comma-separated (for `sbatch --array=...`; empty when none).
    #[arg(long)]
    missing: bool,
}

fn list(v: &[usize]) -> String {
    v.iter()
        .map(|s| s.to_string())
        .collect::<Vec<_>>()
        .join(",")
}

pub fn status(a: StatusArgs) -> Result<()> {
    let s = shard::status(&a.store)?;
    if a.missing {
        println!("{}", list(&s.missing));
        return Ok(());
    }
    println!(
        "{}: {} plan, {} shards, {} done, {} missing",
        a.store.display(),
        s.command,
        s.shards,
        s.done.len(),
        s.missing.len()
    );
    println!("done: {}", list(&s.done));
    println!("missing: {}", list(&s.missing));
    if !s.damaged.is_empty() {
        println!(
            "damaged (finished, but a chunk file changed since: truncated, removed or rewritten; run again): {}",
            list(&s.damaged)
        );
    }
    Ok(())
}

/// Arguments of `geardyn merge`.
#[derive(Args, Debug)]
pub struct MergeArgs {
    /// The plan's store.
    store: PathBuf,
    /// Folder of the command's files (default: the store itself).
    #[arg(long)]
    out: Option<PathBuf>,
}

pub fn merge(a: MergeArgs) -> Result<()> {
    let m = shard::merge(&a.store, a.out.as_deref())?;
    println!(
        "merged {} ({} points) -> {}{}",
        m.command,
        m.points,
        m.out.display(),
        m.parquet
            .as_ref()
            .map_or(String::new(), |p| format!(" (Parquet: {})", p.display()))
    );
    Ok(())
}
