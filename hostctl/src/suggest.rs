//! "Did you mean …?" for mistyped register names.

/// Edit distance (insertions, deletions, substitutions) between two strings,
/// compared case-insensitively.
pub fn distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().map(|c| c.to_ascii_uppercase()).collect();
    let b: Vec<char> = b.chars().map(|c| c.to_ascii_uppercase()).collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    let mut row = vec![0; b.len() + 1];
    for (i, ca) in a.iter().enumerate() {
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let substitute = prev[j] + usize::from(ca != cb);
            row[j + 1] = substitute.min(prev[j + 1] + 1).min(row[j] + 1);
        }
        std::mem::swap(&mut prev, &mut row);
    }
    prev[b.len()]
}

/// A register name without its `REG…_` prefix: `REGDS_DRIVE_REQSPEED` gives
/// `DRIVE_REQSPEED`, `REG_TIMER` gives `TIMER`.
pub fn short_name(name: &str) -> &str {
    // `get`, not `[..3]`: a mistyped name may have a multi-byte character there.
    let upper_reg = name.len() > 3 && name.get(..3).is_some_and(|p| p.eq_ignore_ascii_case("REG"));
    match name.find('_') {
        Some(i) if upper_reg && i + 1 < name.len() => &name[i + 1..],
        _ => name,
    }
}

/// Up to three of `names` close to `wanted`, best first.
///
/// A name is close when its short form contains the wanted text (or the
/// reverse), or is within a few edits of it.
pub fn close_names<'a>(wanted: &str, names: impl IntoIterator<Item = &'a str>) -> Vec<&'a str> {
    let wanted_short = short_name(wanted).to_ascii_uppercase();
    let limit = (wanted_short.len() / 3).max(2);
    let mut scored: Vec<(usize, &'a str)> = names
        .into_iter()
        .filter_map(|name| {
            let short = short_name(name).to_ascii_uppercase();
            let d = distance(&wanted_short, &short);
            let contains = wanted_short.len() >= 3
                && (short.contains(&wanted_short) || wanted_short.contains(&short));
            if d <= limit {
                Some((d, name))
            } else if contains {
                Some((limit + 1, name))
            } else {
                None
            }
        })
        .collect();
    scored.sort_by_key(|&(d, _)| d);
    scored.into_iter().take(3).map(|(_, n)| n).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_counts_edits() {
        assert_eq!(distance("REQSPEED", "reqspeed"), 0);
        assert_eq!(distance("REQSPED", "REQSPEED"), 1);
        assert_eq!(distance("PGAIN", "IGAIN"), 1);
        assert_eq!(distance("", "ABC"), 3);
        assert_eq!(distance("KITTEN", "SITTING"), 3);
    }

    #[test]
    fn short_names_drop_the_prefix() {
        assert_eq!(short_name("REGDS_DRIVE_REQSPEED"), "DRIVE_REQSPEED");
        assert_eq!(short_name("REG_TIMER"), "TIMER");
        assert_eq!(short_name("regll_one_reqpos"), "one_reqpos");
        assert_eq!(short_name("DRIVE_REQSPEED"), "DRIVE_REQSPEED");
        assert_eq!(short_name("REG_"), "REG_");
    }

    #[test]
    fn close_names_rank_by_distance() {
        let names = [
            "REGDS_DRIVE_REQSPEED",
            "REGDS_DRIVE_PGAIN",
            "REGDS_DRIVE_IGAIN",
            "REGDS_STEER_REQPOS",
        ];
        assert_eq!(
            close_names("DRIVE_REQSPED", names),
            ["REGDS_DRIVE_REQSPEED"]
        );
        assert_eq!(
            close_names("REGDS_DRIVE_XGAIN", names),
            ["REGDS_DRIVE_PGAIN", "REGDS_DRIVE_IGAIN"]
        );
        assert_eq!(close_names("REQPOS", names), ["REGDS_STEER_REQPOS"]);
        assert!(close_names("BANANA", names).is_empty());
    }
}
