//! Aligned text tables for people, redrawn in place on a terminal.

/// A table of text cells: the first column is left-aligned, the rest right.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Table {
    /// Header rows (e.g. names, then units).
    pub headers: Vec<Vec<String>>,
    /// Body rows.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// The table as lines, columns separated by two spaces, no trailing blanks.
    pub fn lines(&self) -> Vec<String> {
        let all: Vec<&Vec<String>> = self.headers.iter().chain(self.rows.iter()).collect();
        let columns = all.iter().map(|r| r.len()).max().unwrap_or(0);
        let widths: Vec<usize> = (0..columns)
            .map(|c| {
                all.iter()
                    .filter_map(|r| r.get(c))
                    .map(|s| s.chars().count())
                    .max()
                    .unwrap_or(0)
            })
            .collect();
        all.iter()
            .map(|row| {
                let mut line = String::new();
                for (c, width) in widths.iter().enumerate() {
                    let cell = row.get(c).map(String::as_str).unwrap_or("");
                    let pad = width - cell.chars().count();
                    if c == 0 {
                        line.push_str(cell);
                        line.push_str(&" ".repeat(pad));
                    } else {
                        line.push_str("  ");
                        line.push_str(&" ".repeat(pad));
                        line.push_str(cell);
                    }
                }
                line.trim_end().to_owned()
            })
            .collect()
    }
}

/// Turns successive frames of lines into output text: on a terminal each
/// frame overwrites the previous one, otherwise frames follow each other.
#[derive(Debug)]
pub struct Screen {
    in_place: bool,
    /// Terminal rows the previous frame took: a line longer than the terminal is wide
    /// wraps onto more than one, and the next frame must go back over all of them.
    drawn: usize,
    /// The terminal's width in columns, asked at each frame (it may be resized).
    width: fn() -> Option<usize>,
}

impl Screen {
    /// A screen that redraws in place when `in_place` (a terminal, whose width in
    /// columns `width` tells at each frame).
    pub fn new(in_place: bool, width: fn() -> Option<usize>) -> Self {
        Self {
            in_place,
            drawn: 0,
            width,
        }
    }

    /// The text that shows `lines` as the new frame.
    pub fn frame(&mut self, lines: &[String]) -> String {
        let mut out = String::new();
        if self.in_place {
            if self.drawn > 0 {
                // Cursor up to the first row of the previous frame.
                out.push_str(&format!("\x1b[{}A\r", self.drawn));
            }
            for line in lines {
                out.push_str(line);
                // Clear what is left of a longer previous line.
                out.push_str("\x1b[K\n");
            }
            // Clear lines left over from a taller previous frame.
            out.push_str("\x1b[J");
            let width = (self.width)().filter(|&w| w > 0);
            self.drawn = lines
                .iter()
                .map(|l| match width {
                    Some(w) => l.chars().count().div_ceil(w).max(1),
                    None => 1,
                })
                .sum();
        } else {
            if self.drawn > 0 {
                out.push('\n');
            }
            for line in lines {
                out.push_str(line);
                out.push('\n');
            }
            self.drawn = lines.len();
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strings(cells: &[&str]) -> Vec<String> {
        cells.iter().map(|s| s.to_string()).collect()
    }

    fn sample() -> Table {
        Table {
            headers: vec![
                strings(&["dev", "TIMER", "ACTUALSPEED"]),
                strings(&["", "ms", "ticks/s"]),
            ],
            rows: vec![
                strings(&["1", "65535", "-4000.000"]),
                strings(&["12", "7", "0.000"]),
            ],
        }
    }

    #[test]
    fn columns_are_aligned() {
        assert_eq!(
            sample().lines(),
            [
                "dev  TIMER  ACTUALSPEED",
                "        ms      ticks/s",
                "1    65535    -4000.000",
                "12       7        0.000",
            ]
        );
    }

    #[test]
    fn frames_follow_each_other_off_a_terminal() {
        let mut screen = Screen::new(false, || None);
        let lines = strings(&["a", "b"]);
        assert_eq!(screen.frame(&lines), "a\nb\n");
        assert_eq!(screen.frame(&lines), "\na\nb\n");
    }

    #[test]
    fn frames_overwrite_on_a_terminal() {
        let mut screen = Screen::new(true, || None);
        assert_eq!(
            screen.frame(&strings(&["a", "b"])),
            "a\x1b[K\nb\x1b[K\n\x1b[J"
        );
        assert_eq!(screen.frame(&strings(&["c"])), "\x1b[2A\rc\x1b[K\n\x1b[J");
        assert_eq!(screen.frame(&strings(&["d"])), "\x1b[1A\rd\x1b[K\n\x1b[J");
    }

    #[test]
    fn a_frame_goes_back_over_the_rows_its_long_lines_wrapped_onto() {
        // On a 10-column terminal: 10 characters take one row, 11 two, 25 three.
        let mut screen = Screen::new(true, || Some(10));
        let long = [
            "x".repeat(10),
            "y".repeat(11),
            String::new(),
            "z".repeat(25),
        ];
        screen.frame(&long);
        assert_eq!(screen.frame(&strings(&["a"])), "\x1b[7A\ra\x1b[K\n\x1b[J");
        assert_eq!(screen.frame(&strings(&["b"])), "\x1b[1A\rb\x1b[K\n\x1b[J");
    }
}
