//! A static bound on an AVR image's stack: the deepest its call graph can go, with each
//! interrupt priority level preempting at most once, as the executor guarantees.
//!
//! The emulator tests paint the free RAM and read back the deepest frame a run reached:
//! that is what one run did, not what the image can do. This module reads the image's
//! disassembly (`avr-objdump`, the AVR binutils' own decoder) and bounds every path:
//!
//! - a function's own bytes are its `push`es, the frame its prologue takes from SP
//!   (`in r28, 0x3d` … `subi`/`sbci`/`sbiw` … `out 0x3d, r28`) and any `rcall .+0`
//!   (two bytes taken by a call to the next instruction);
//! - a `call`/`rcall` adds the two-byte return address and the callee's depth; a jump or
//!   branch out of the function adds the target's depth (a tail call);
//! - an indirect call (`icall`/`ijmp`) may reach any function whose word address the
//!   image loads into a register pair (`ldi` lo, then `ldi` hi) or keeps in `.data`;
//! - recursion, or a call into no known function, is an error, never a guess.
//!
//! Counting every `push` of a function (not only its prologue's) and taking the largest
//! frame make each figure an upper bound. [`Program::bound`] then adds, to the deepest
//! path of `main` with interrupts on, the deepest task of each priority level plus the
//! two bytes the hardware pushes on entry: within a level the executor masks every
//! source of that level, so no two tasks of one level are ever on the stack together.
//! The `init` path (`___exec_setup`) runs with interrupts off and counts alone.
//!
//! Each task's level comes from the image itself: the executor's `app!` records it as an
//! absolute symbol `__exec_level_<vector>` (no flash), so the bound follows the tasks'
//! declarations with no copy of them here.

use std::collections::HashMap;
use std::path::Path;
use std::process::Command;

/// One function of the image.
#[derive(Debug, Clone)]
struct Function {
    name: String,
    start: u32,
    end: u32,
}

/// A control transfer to another function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Edge {
    /// `call`/`rcall`: the callee runs above a two-byte return address.
    Call(u32),
    /// A jump or branch out of the function: the target runs in its place.
    Jump(u32),
    /// `icall`: any address-taken function, above a return address.
    IndirectCall,
    /// `ijmp`: any address-taken function, in its place.
    IndirectJump,
}

/// What one function needs of the stack by itself, and where it goes next.
#[derive(Debug, Clone, Default)]
struct Cost {
    /// Pushes, the prologue's frame and `rcall .+0` allocations, bytes.
    own: u32,
    edges: Vec<Edge>,
}

/// One decoded instruction line.
#[derive(Debug)]
struct Insn {
    addr: u32,
    mnemonic: String,
    operands: String,
    /// The absolute address objdump prints after `;` for calls, jumps and branches.
    target: Option<u32>,
}

/// An image's functions, their costs and its interrupt vectors.
#[derive(Debug)]
pub struct Program {
    functions: Vec<Function>,
    costs: Vec<Cost>,
    /// Indices of the functions whose address the image takes.
    address_taken: Vec<usize>,
    /// (vector number, handler's function index), for vectors that do not go to
    /// `__bad_interrupt`.
    vectors: Vec<(u8, usize)>,
    /// `__heap_start`, the first byte past the static data, as a data address.
    heap_start: Option<u32>,
    /// (vector number, priority level) of each task the executor declared, from the
    /// `__exec_level_<vector>` symbols.
    levels: Vec<(u8, u8)>,
}

/// The bound and where it comes from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Bound {
    /// `main` with interrupts on (its `init` call left out), from the startup's call.
    pub main: u32,
    /// `main` including `init`, which runs with interrupts off.
    pub main_with_init: u32,
    /// Per priority level, lowest first: (level, deepest task's handler, its depth with
    /// the two bytes of its entry).
    pub levels: Vec<(u8, String, u32)>,
    /// The bound: the larger of `main_with_init` and `main` plus every level.
    pub total: u32,
}

/// The prefix of the absolute symbols in which the executor records each task's level.
const LEVEL_SYMBOL: &str = "__exec_level_";

/// The bytes of an ATmega328P vector table slot: vector n sits at 4·n.
const VECTOR_SLOT: u32 = 4;
/// Vectors of the ATmega328P (reset included).
const VECTORS: u32 = 26;

fn hex(s: &str) -> Option<u32> {
    u32::from_str_radix(s.trim().trim_start_matches("0x"), 16).ok()
}

fn number(s: &str) -> Option<u32> {
    let s = s.trim();
    if s.starts_with("0x") {
        hex(s)
    } else {
        s.parse().ok()
    }
}

/// Register number of `rNN`.
fn register(s: &str) -> Option<u32> {
    s.trim().strip_prefix('r')?.parse().ok()
}

/// The code symbols of `.text` in `avr-objdump -t` (`ADDR flags .text SIZE [.hidden]
/// NAME`): every sized symbol but the data objects (flag `O`), so functions (flag `F`) and
/// the C library's assembly routines, which have no type.
fn code_symbols(symbols: &str) -> Vec<Function> {
    let mut out: Vec<Function> = symbols
        .lines()
        .filter_map(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            let section = t.iter().position(|&w| w == ".text")?;
            let is_object = t.get(1..section).is_some_and(|flags| flags.contains(&"O"));
            let size = hex(t.get(section + 1)?)?;
            (!is_object && size > 0).then_some(())?;
            let start = hex(t.first()?)?;
            Some(Function {
                name: t.last()?.to_string(),
                start,
                end: start + size,
            })
        })
        .collect();
    out.sort_by_key(|f| f.start);
    out
}

/// The `(vector, level)` of every `__exec_level_<vector>` absolute symbol (`ADDR g
/// *ABS* 0 NAME`, the level as the address), sorted by vector.
fn task_levels(symbols: &str) -> Result<Vec<(u8, u8)>, String> {
    let mut out = Vec::new();
    for line in symbols.lines() {
        let t: Vec<&str> = line.split_whitespace().collect();
        let Some(vector) = t.last().and_then(|n| n.strip_prefix(LEVEL_SYMBOL)) else {
            continue;
        };
        let level = t.first().and_then(|a| hex(a));
        let (Ok(vector), Some(Ok(level))) = (vector.parse(), level.map(u8::try_from)) else {
            return Err(format!("unreadable task level symbol: {line}"));
        };
        out.push((vector, level));
    }
    out.sort_unstable();
    Ok(out)
}

/// The instruction lines of `avr-objdump -d --no-show-raw-insn`.
fn instructions(disassembly: &str) -> Vec<Insn> {
    disassembly
        .lines()
        .filter_map(|l| {
            let (addr, rest) = l.split_once(":\t")?;
            let addr = hex(addr)?;
            let (code, comment) = match rest.split_once(';') {
                Some((c, k)) => (c, Some(k)),
                None => (rest, None),
            };
            let mut parts = code.trim().splitn(2, '\t');
            let mnemonic = parts.next()?.trim().to_string();
            let operands = parts.next().unwrap_or("").trim().to_string();
            let target = comment
                .and_then(|k| k.split_whitespace().next())
                .filter(|w| w.starts_with("0x"))
                .and_then(hex)
                .or_else(|| {
                    // `call 0x20d8` / `jmp 0x158` without a comment.
                    matches!(mnemonic.as_str(), "call" | "jmp")
                        .then(|| hex(&operands))
                        .flatten()
                });
            Some(Insn {
                addr,
                mnemonic,
                operands,
                target,
            })
        })
        .collect()
}

fn operand_pair(ops: &str) -> Option<(&str, &str)> {
    let (a, b) = ops.split_once(',')?;
    Some((a.trim(), b.trim()))
}

/// The frame a prologue takes: Y is loaded from SP, moved down, and stored back.
#[derive(Default)]
struct FrameTracker {
    /// Some(delta) between `in r28, 0x3d` and `out 0x3d, r28`: bytes Y moved down.
    open: Option<u16>,
    largest: u32,
}

impl FrameTracker {
    fn step(&mut self, i: &Insn) {
        let Some((a, b)) = operand_pair(&i.operands) else {
            return;
        };
        match (i.mnemonic.as_str(), a, b) {
            ("in", "r28", "0x3d") => self.open = Some(0),
            ("out", "0x3d", "r28") => {
                if let Some(delta) = self.open.take() {
                    let taken = delta as i16;
                    self.largest = self.largest.max(u32::try_from(taken).unwrap_or(0));
                }
            }
            (m, reg, k) => {
                let (Some(delta), Some(k)) = (self.open.as_mut(), number(k)) else {
                    return;
                };
                let k = k as u16;
                *delta = match (m, reg) {
                    ("sbiw", "r28") | ("subi", "r28") => delta.wrapping_add(k),
                    ("sbci", "r29") => delta.wrapping_add(k << 8),
                    ("adiw", "r28") => delta.wrapping_sub(k),
                    _ => *delta,
                };
            }
        }
    }
}

impl Program {
    /// Reads an ELF image: its symbols and code through `avr-objdump`, its `.data`
    /// through the harness's ELF reader.
    pub fn of_elf(path: &Path) -> Result<Program, String> {
        let objdump = |args: &[&str]| -> Result<String, String> {
            let done = Command::new("avr-objdump")
                .args(args)
                .arg(path)
                .output()
                .map_err(|e| {
                    format!(
                        "cannot run avr-objdump ({e}): install the AVR binutils (scripts/setup.sh)"
                    )
                })?;
            if !done.status.success() {
                return Err(format!(
                    "avr-objdump {args:?} {} failed: {}",
                    path.display(),
                    String::from_utf8_lossy(&done.stderr)
                ));
            }
            Ok(String::from_utf8_lossy(&done.stdout).into_owned())
        };
        let symbols = objdump(&["-t"])?;
        let disassembly = objdump(&["-d", "--no-show-raw-insn"])?;
        // Function pointers the image stores: `.data` (vtables live there on the AVR).
        // The flash tables (`shared::progmem`) hold plain numbers, read with `lpm`:
        // scanning them only finds look-alikes.
        let elf = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let stored = harness::data_initial_bytes(&elf)?;
        Program::parse(&symbols, &disassembly, &stored)
    }

    /// Builds the program from objdump's symbol table (`-t`) and disassembly
    /// (`-d --no-show-raw-insn`); every 16-bit word of `stored` (data the image keeps)
    /// that is a function's word address is taken as a pointer to it.
    pub fn parse(symbols: &str, disassembly: &str, stored: &[u8]) -> Result<Program, String> {
        let functions = code_symbols(symbols);
        if functions.is_empty() {
            return Err("no function symbols (F .text) in the symbol table".into());
        }
        let insns = instructions(disassembly);
        let index_of = |addr: u32| -> Option<usize> {
            let i = functions
                .partition_point(|f| f.start <= addr)
                .checked_sub(1)?;
            (addr < functions[i].end).then_some(i)
        };
        let start_of: HashMap<u32, usize> = functions
            .iter()
            .enumerate()
            .map(|(i, f)| (f.start, i))
            .collect();

        let mut costs = vec![Cost::default(); functions.len()];
        let mut frames: Vec<FrameTracker> = (0..functions.len())
            .map(|_| FrameTracker::default())
            .collect();
        let mut taken = Vec::new();
        let mut vectors = Vec::new();
        for (n, i) in insns.iter().enumerate() {
            if i.addr < VECTORS * VECTOR_SLOT && i.addr % VECTOR_SLOT == 0 {
                if let Some(&f) = i.target.and_then(|t| start_of.get(&t)) {
                    vectors.push(((i.addr / VECTOR_SLOT) as u8, f));
                }
            }
            // A word address in a register pair: `ldi rN, lo` then `ldi rN+1, hi`, the
            // two instructions LLVM makes of a 16-bit constant.
            if i.mnemonic == "ldi" {
                if let Some((r, lo)) = operand_pair(&i.operands)
                    .and_then(|(r, k)| Some((register(r)?, number(k)?)))
                    .filter(|(r, _)| r % 2 == 0)
                {
                    let hi = insns
                        .get(n + 1)
                        .filter(|j| j.mnemonic == "ldi")
                        .and_then(|j| {
                            let (q, k) = operand_pair(&j.operands)?;
                            (register(q)? == r + 1).then(|| number(k))?
                        });
                    if let Some(&f) = hi.and_then(|hi| start_of.get(&(2 * ((hi << 8) | lo)))) {
                        taken.push(f);
                    }
                }
            }
            let Some(f) = index_of(i.addr) else {
                continue;
            };
            frames[f].step(i);
            let cost = &mut costs[f];
            let inside = |t: u32| (functions[f].start..functions[f].end).contains(&t);
            match i.mnemonic.as_str() {
                "push" => cost.own += 1,
                "rcall" if i.operands == ".+0" => cost.own += 2,
                "call" | "rcall" => {
                    let t = i
                        .target
                        .ok_or_else(|| format!("call without a target at {:#x}", i.addr))?;
                    let callee = start_of.get(&t).ok_or_else(|| {
                        format!("call at {:#x} to {t:#x}, which starts no function", i.addr)
                    })?;
                    cost.edges.push(Edge::Call(*callee as u32));
                }
                "icall" | "eicall" => cost.edges.push(Edge::IndirectCall),
                "ijmp" | "eijmp" => cost.edges.push(Edge::IndirectJump),
                m if m == "jmp" || m == "rjmp" || m.starts_with("br") => {
                    if let Some(t) = i.target.filter(|&t| !inside(t)) {
                        let target = index_of(t).ok_or_else(|| {
                            format!("jump at {:#x} to {t:#x}, outside every function", i.addr)
                        })?;
                        cost.edges.push(Edge::Jump(target as u32));
                    }
                }
                _ => {}
            }
        }
        for (cost, frame) in costs.iter_mut().zip(&frames) {
            cost.own += frame.largest;
        }
        for w in stored.windows(2) {
            let word = u32::from(u16::from_le_bytes([w[0], w[1]]));
            if let Some(&f) = start_of.get(&(2 * word)) {
                taken.push(f);
            }
        }
        taken.sort_unstable();
        taken.dedup();
        let heap_start = symbols
            .lines()
            .filter(|l| l.split_whitespace().last() == Some("__heap_start"))
            .find_map(|l| hex(l.split_whitespace().next()?));
        Ok(Program {
            functions,
            costs,
            address_taken: taken,
            vectors,
            heap_start: heap_start.map(|a| a & 0xffff),
            levels: task_levels(symbols)?,
        })
    }

    fn find(&self, name: &str) -> Result<usize, String> {
        self.functions
            .iter()
            .position(|f| f.name == name)
            .ok_or_else(|| format!("no function named {name}"))
    }

    /// The deepest the stack goes below the entry of function `f` (its return address
    /// not included), leaving out calls and jumps to functions `skip` accepts.
    fn depth_of(
        &self,
        f: usize,
        skip: &dyn Fn(&str) -> bool,
        memo: &mut HashMap<usize, u32>,
        path: &mut Vec<usize>,
    ) -> Result<u32, String> {
        if let Some(&d) = memo.get(&f) {
            return Ok(d);
        }
        if path.contains(&f) {
            let names: Vec<&str> = path
                .iter()
                .map(|&p| self.functions[p].name.as_str())
                .collect();
            return Err(format!(
                "recursion through {} (path {names:?}): no static bound",
                self.functions[f].name
            ));
        }
        path.push(f);
        let mut below = 0;
        for &edge in &self.costs[f].edges {
            let (targets, ret): (Vec<usize>, u32) = match edge {
                Edge::Call(t) => (vec![t as usize], 2),
                Edge::Jump(t) => (vec![t as usize], 0),
                Edge::IndirectCall | Edge::IndirectJump if self.address_taken.is_empty() => {
                    return Err(format!(
                        "{} calls through a pointer, and no function's address is taken",
                        self.functions[f].name
                    ))
                }
                Edge::IndirectCall => (self.address_taken.clone(), 2),
                Edge::IndirectJump => (self.address_taken.clone(), 0),
            };
            for t in targets {
                if skip(&self.functions[t].name) {
                    continue;
                }
                below = below.max(ret + self.depth_of(t, skip, memo, path)?);
            }
        }
        path.pop();
        let d = self.costs[f].own + below;
        memo.insert(f, d);
        Ok(d)
    }

    /// The deepest the stack goes below a call of `name` (its return address not
    /// included).
    pub fn depth(&self, name: &str) -> Result<u32, String> {
        self.depth_of(
            self.find(name)?,
            &|_| false,
            &mut HashMap::new(),
            &mut Vec::new(),
        )
    }

    /// Static RAM (`.data` and `.bss`): from the start of the ATmega328P's RAM, 0x100,
    /// to `__heap_start`.
    pub fn static_ram(&self) -> Result<u32, String> {
        let end = self
            .heap_start
            .ok_or("no __heap_start in the symbol table")?;
        end.checked_sub(0x100)
            .ok_or_else(|| format!("__heap_start {end:#x} lies below RAM"))
    }

    /// The function whose code holds byte address `addr`, by its symbol name.
    pub fn function_at(&self, addr: u32) -> Option<&str> {
        let i = self
            .functions
            .partition_point(|f| f.start <= addr)
            .checked_sub(1)?;
        let f = &self.functions[i];
        (addr < f.end).then_some(f.name.as_str())
    }

    /// The vectors with a handler of their own: (number, handler's name).
    pub fn vectors(&self) -> Vec<(u8, &str)> {
        self.vectors
            .iter()
            .filter(|&&(n, _)| n != 0)
            .map(|&(n, f)| (n, self.functions[f].name.as_str()))
            .collect()
    }

    /// The executor's tasks as (vector, priority level), by vector, as the image records
    /// them.
    pub fn levels(&self) -> &[(u8, u8)] {
        &self.levels
    }

    /// The stack bound, each task at the level the image records for it. Every vector
    /// with a handler must be a task's, and every task's vector must have a handler.
    pub fn bound(&self) -> Result<Bound, String> {
        let levels = self.levels.as_slice();
        let handled: Vec<u8> = self.vectors().iter().map(|&(n, _)| n).collect();
        let tasks: Vec<u8> = levels.iter().map(|&(n, _)| n).collect();
        if handled != tasks {
            return Err(format!(
                "the image handles vectors {handled:?} but records executor tasks on \
                 {tasks:?}: a handler outside `executor::app!` has no known level (declare \
                 it as a task), or the image was linked without the executor's level symbols"
            ));
        }
        let init = |name: &str| name.ends_with("___exec_setup");
        let main = self.find("main")?;
        // The startup code calls main: two bytes of return address.
        let with_init = 2 + self.depth(&self.functions[main].name)?;
        let without = 2 + self.depth_of(main, &init, &mut HashMap::new(), &mut Vec::new())?;
        let mut per_level: Vec<(u8, String, u32)> = Vec::new();
        for &(vector, level) in levels {
            let &(_, f) = self
                .vectors
                .iter()
                .find(|&&(n, _)| n == vector)
                .ok_or_else(|| format!("vector {vector} has no handler"))?;
            let d = 2 + self.depth_of(f, &|_| false, &mut HashMap::new(), &mut Vec::new())?;
            let name = self.functions[f].name.clone();
            match per_level.iter_mut().find(|(l, _, _)| *l == level) {
                Some(e) if e.2 >= d => {}
                Some(e) => *e = (level, name, d),
                None => per_level.push((level, name, d)),
            }
        }
        per_level.sort_by_key(|e| e.0);
        let running = without + per_level.iter().map(|e| e.2).sum::<u32>();
        Ok(Bound {
            main: without,
            main_with_init: with_init,
            total: running.max(with_init),
            levels: per_level,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SYMBOLS: &str = "\
00000100 g     F .text	0000000a main
0000010a l     F .text	0000000e leaf
00000118 g     F .text	00000004 __vector_5
0000011c l     F .text	00000004 x___exec_setup
00000120 g       .text	00000004 .hidden pointed
00000068 l     O .text	00000004 TABLE
00800249 g       *ABS*	00000000 __heap_start
00000001 g       *ABS*	00000000 __exec_level_5
";

    const CODE: &str = "\
   0:\tjmp\t0x100\t; 0x100 <main>
  14:\tjmp\t0x118\t; 0x118 <__vector_5>
  18:\tjmp\t0x13a\t; 0x13a <__bad_interrupt>
 100:\tcall\t0x11c\t; 0x11c <x___exec_setup>
 104:\tldi\tr24, 0x90\t; 144
 106:\tldi\tr25, 0x00\t; 0
 108:\ticall
 10a:\tpush\tr28
 10c:\tpush\tr29
 10e:\tin\tr28, 0x3d\t; 61
 110:\tin\tr29, 0x3e\t; 62
 112:\tsubi\tr28, 0x6C\t; 108
 114:\tsbci\tr29, 0x00\t; 0
 116:\tout\t0x3d, r28\t; 61
 118:\tpush\tr0
 11a:\trcall\t.-18     \t; 0x10a <leaf>
 11c:\trcall\t.+0      \t; 0x11e <x___exec_setup+0x2>
 11e:\tret
 120:\tpush\tr2
 122:\tret
";

    fn program() -> Program {
        Program::parse(SYMBOLS, CODE, &[]).expect("parses")
    }

    #[test]
    fn a_function_costs_its_pushes_and_its_frame() {
        // leaf: two pushes and a frame of 108 bytes.
        assert_eq!(program().depth("leaf"), Ok(110));
    }

    #[test]
    fn an_address_is_named_by_the_function_that_holds_it() {
        let p = program();
        assert_eq!(p.function_at(0x100), Some("main"));
        assert_eq!(p.function_at(0x109), Some("main"));
        assert_eq!(p.function_at(0x10a), Some("leaf"));
        // Before the first function, and in the table (an object, not code).
        assert_eq!(p.function_at(0x68), None);
        // Past the last function's end.
        assert_eq!(p.function_at(0x124), None);
    }

    #[test]
    fn a_call_adds_its_return_address_and_the_callee() {
        let p = program();
        // __vector_5: one push, then a call of leaf.
        assert_eq!(p.depth("__vector_5"), Ok(1 + 2 + 110));
        // rcall .+0 takes two bytes and calls nothing.
        assert_eq!(p.depth("x___exec_setup"), Ok(2));
    }

    #[test]
    fn an_indirect_call_reaches_every_function_whose_address_is_loaded() {
        // main: a call of init (2 + 2), and an icall of `pointed` (0x90 words = 0x120).
        // The deeper of the two is init's: 2 + 2 against 2 + 1.
        assert_eq!(program().depth("main"), Ok(4));
        let no_pointer = CODE.replace("ldi\tr25, 0x00", "ldi\tr25, 0x07");
        let err = Program::parse(SYMBOLS, &no_pointer, &[])
            .expect("parses")
            .depth("main")
            .unwrap_err();
        assert!(err.contains("no function's address is taken"), "{err}");
        // The same pointer stored as data.
        let p = Program::parse(SYMBOLS, &no_pointer, &[0x07, 0x90, 0x00]).expect("parses");
        assert_eq!(p.depth("main"), Ok(4));
    }

    #[test]
    fn the_bound_adds_one_task_per_level_to_main_without_init() {
        let p = program();
        assert_eq!(p.vectors(), vec![(5, "__vector_5")]);
        assert_eq!(p.levels(), &[(5, 1)]);
        let b = p.bound().expect("bound");
        // main without init: its icall of `pointed` (2 + 1), from the startup (2).
        assert_eq!(b.main, 2 + 3);
        assert_eq!(b.main_with_init, 2 + 4);
        assert_eq!(b.levels, vec![(1, "__vector_5".to_string(), 2 + 113)]);
        assert_eq!(b.total, 5 + 115);
        assert_eq!(p.static_ram(), Ok(0x149));
    }

    #[test]
    fn a_level_is_read_from_its_symbol() {
        let symbols = SYMBOLS.replace("00000001 g       *ABS*", "00000003 g       *ABS*");
        let p = Program::parse(&symbols, CODE, &[]).expect("parses");
        assert_eq!(p.levels(), &[(5, 3)]);
        assert_eq!(p.bound().expect("bound").levels[0].0, 3);
        let bad = SYMBOLS.replace("00000001 g       *ABS*", "00000301 g       *ABS*");
        let err = Program::parse(&bad, CODE, &[]).unwrap_err();
        assert!(err.contains("unreadable task level"), "{err}");
    }

    #[test]
    fn a_handler_without_a_recorded_level_is_refused() {
        // A vector handled outside the executor, or an image without the level symbols.
        let symbols = SYMBOLS.replace("__exec_level_5", "something_else");
        let err = Program::parse(&symbols, CODE, &[])
            .expect("parses")
            .bound()
            .unwrap_err();
        assert!(err.contains("has no known level"), "{err}");
        // A task whose vector has no handler.
        let symbols = format!("{SYMBOLS}00000002 g       *ABS*\t00000000 __exec_level_6\n");
        let err = Program::parse(&symbols, CODE, &[])
            .expect("parses")
            .bound()
            .unwrap_err();
        assert!(err.contains("records executor tasks on [5, 6]"), "{err}");
    }

    #[test]
    fn recursion_has_no_bound() {
        let code = CODE.replace(
            "rcall\t.-18     \t; 0x10a <leaf>",
            "rcall\t.-4\t; 0x118 <__vector_5>",
        );
        let err = Program::parse(SYMBOLS, &code, &[])
            .expect("parses")
            .depth("__vector_5")
            .unwrap_err();
        assert!(err.contains("recursion"), "{err}");
    }

    #[test]
    fn a_call_into_no_function_is_an_error() {
        let code = CODE.replace("; 0x10a <leaf>", "; 0x10c <leaf+0x2>");
        let err = Program::parse(SYMBOLS, &code, &[]).unwrap_err();
        assert!(err.contains("starts no function"), "{err}");
    }
}
