//! Numbers in plain words, for the text the commands print.

/// `n` and `word`, with an `s` unless `n` is 1 (`1 step`, `2 steps`).
pub fn plural(n: usize, word: &str) -> String {
    format!("{} {word}{}", thousands(n), if n == 1 { "" } else { "s" })
}

/// `n` with commas between groups of three digits (`12,444`).
pub fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_numbers() {
        assert_eq!(thousands(0), "0");
        assert_eq!(thousands(999), "999");
        assert_eq!(thousands(12444), "12,444");
        assert_eq!(thousands(1234567), "1,234,567");
        assert_eq!(plural(1, "step"), "1 step");
        assert_eq!(plural(2, "piece"), "2 pieces");
        assert_eq!(plural(1000, "step"), "1,000 steps");
    }
}
