//! Emulator benchmark of the executor (`exec_bench`), in cycles, with the goals of the
//! design as assertions so that a regression fails CI:
//! - dispatch overhead beyond a plain handler with the same body: at most 40 cycles;
//! - lock plus unlock: at most 10 cycles at the top ceiling, at most 40 where sources
//!   are masked.
//!
//! Run with `--nocapture` to print the table that docs/executor.md quotes.

mod executor_support;

use std::collections::HashMap;

use executor_support::{boot, fields, report};

/// The top priority of the benchmark application (its level-3 task is the top task).
const TOP: u32 = 3;

struct Bench {
    levels: Vec<HashMap<String, u32>>,
    bare: HashMap<String, u32>,
    bare_min: HashMap<String, u32>,
}

fn run() -> Bench {
    let mut avr = boot("exec_bench");
    let levels = (1..=TOP)
        .map(|l| fields(&report(&mut avr, &format!("bench level={l}"), 50_000)))
        .collect();
    let bare = fields(&report(&mut avr, "bench bare ", 50_000));
    let bare_min = fields(&report(&mut avr, "bench bare_min ", 50_000));
    Bench {
        levels,
        bare,
        bare_min,
    }
}

#[test]
fn dispatch_overhead_is_at_most_40_cycles_at_every_level() {
    let b = run();
    println!("level | entry | exit | total | overhead | lock+unlock");
    for (i, l) in b.levels.iter().enumerate() {
        println!(
            "{} | {} | {} | {} | {} | {}",
            i + 1,
            l["entry"],
            l["exit"],
            l["total"],
            l["total"] as i64 - b.bare["total"] as i64,
            l["lock"]
        );
    }
    for (name, h) in [("bare", &b.bare), ("bare_min", &b.bare_min)] {
        println!("{name} | {} | {} | {} |", h["entry"], h["exit"], h["total"]);
    }
    for (i, l) in b.levels.iter().enumerate() {
        let overhead = l["total"].saturating_sub(b.bare["total"]);
        assert!(overhead <= 40, "level {}: {overhead} cycles", i + 1);
        assert!(l["entry"] >= b.bare["entry"], "level {}", i + 1);
    }
    // A top-priority task is a plain handler: no masking, no overhead at all.
    let top = &b.levels[TOP as usize - 1];
    assert_eq!(top["total"], b.bare["total"]);
    // Below the top, a task does pay for masking: the measurement sees it.
    assert!(b.levels[0]["total"] > b.bare["total"] + 10);
    assert!(b.levels[1]["total"] > b.levels[0]["total"]);
}

#[test]
fn lock_and_unlock_stay_within_their_budgets() {
    let b = run();
    for (i, l) in b.levels.iter().enumerate() {
        let level = i as u32 + 1;
        let budget = if level == TOP { 10 } else { 40 };
        assert!(
            l["lock"] <= budget,
            "ceiling {level}: {} cycles (budget {budget})",
            l["lock"]
        );
        assert!(l["lock"] > 0, "ceiling {level}: the lock was measured");
    }
}

#[test]
fn the_classic_prologue_is_what_separates_the_two_baselines() {
    // `bare_min` lacks the inline `nop`, so LLVM neither saves nor clears r1: 5 cycles
    // of prologue and epilogue, plus the `nop` itself.
    let b = run();
    assert_eq!(b.bare["total"] - b.bare_min["total"], 6);
}
