//! Property tests: whatever the text, the reader neither panics nor hangs.

use super::*;
use proptest::prelude::*;

/// Reads up to `max_blocks` blocks (a program may loop forever giving blocks: that is its
/// consumer's business), with loops limited to 1000 passes and 20000 lines read again without a block. Returns how
/// many blocks came before the end or an error.
fn drive<S: Source>(source: S, block_delete: bool, max_blocks: usize) -> usize {
    let mut r = Reader::new(source, block_delete);
    r.max_passes = 1_000;
    r.max_reread = 20_000;
    let mut p = Params::new();
    for n in 0..max_blocks {
        match r.next_block(&mut p) {
            Ok(Some(b)) => assert!(!b.is_empty()),
            Ok(None) | Err(_) => {
                // Done for good.
                assert_eq!(r.next_block(&mut p), Ok(None));
                return n;
            }
        }
    }
    max_blocks
}

/// Up to 300 blocks of `r`, and its error if any.
fn collect<S: Source>(mut r: Reader<S>) -> Vec<Result<Block, GcodeError>> {
    let mut p = Params::new();
    let mut out = Vec::new();
    for _ in 0..300 {
        match r.next_block(&mut p) {
            Ok(Some(b)) => out.push(Ok(b)),
            Ok(None) => break,
            Err(e) => {
                out.push(Err(e));
                break;
            }
        }
    }
    out
}

/// Pieces of G-code, joined at random.
const TOKENS: &[&str] = &[
    "G1",
    "G0",
    "g38.2",
    "X",
    "Y1.5",
    "Z-.5",
    "F#1",
    "M3",
    "M2",
    "N10",
    "#1",
    "#2",
    "##1",
    "#<a>",
    "#<_b>",
    "#[1+1]",
    "=",
    "[",
    "]",
    "+",
    "-",
    "*",
    "**",
    "/",
    "MOD",
    "EQ",
    "LT",
    "AND",
    "XOR",
    "1",
    "0",
    "-2.5",
    ".",
    "1e5",
    "sin",
    "atan[1]/",
    "exists[",
    "abs",
    "sqrt",
    "o1",
    "o2",
    "o<s>",
    " sub",
    " endsub",
    " call",
    " return",
    " if",
    " elseif",
    " else",
    " endif",
    " while",
    " endwhile",
    " do",
    " repeat",
    " endrepeat",
    " break",
    " continue",
    "(",
    ")",
    "(MSG,#1 #<a>)",
    "(print,%d#2)",
    ";",
    "%",
    "\n",
    "\n",
    "\n",
    "\n",
    " ",
    "\t",
    "\r",
    "\u{e9}",
    "\0",
    "<",
    ">",
    "$",
];

/// Whole lines, so that the control flow is exercised more than by token soup.
const LINES: &[&str] = &[
    "#1=[#1+1]",
    "#2=[#2-1]",
    "#<a>=#1",
    "G1 X#1 Y#2",
    "(MSG, #1 #<a>)",
    "o1 while [#1 LT 5]",
    "o1 endwhile",
    "o1 do",
    "o1 while [#2 GT -3]",
    "o2 repeat [3]",
    "o2 endrepeat",
    "o1 if [#1 MOD 2]",
    "o1 elseif [#2]",
    "o1 else",
    "o1 endif",
    "o1 break",
    "o2 continue",
    "o<s> sub",
    "o<s> endsub",
    "o<s> return [#1]",
    "o<s> call [#1] [2]",
    "o<t> call",
    "o<t> sub",
    "o<t> endsub [1]",
    "X#<_value>",
    "%",
    "/G0 X1",
    "M2",
    "",
];

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    #[test]
    fn random_text_never_panics(bytes in proptest::collection::vec(any::<u8>(), 0..400),
                                bd in any::<bool>()) {
        let text = String::from_utf8_lossy(&bytes).into_owned();
        drive(TextSource::new(text), bd, 1_000);
    }

    #[test]
    fn token_soup_never_panics(picks in proptest::collection::vec(0..TOKENS.len(), 0..120),
                               bd in any::<bool>()) {
        let text: String = picks.iter().map(|&i| TOKENS[i]).collect();
        drive(TextSource::new(text), bd, 1_000);
    }

    #[test]
    fn random_programs_never_panic_or_hang(
        picks in proptest::collection::vec(0..LINES.len(), 0..60), bd in any::<bool>()
    ) {
        let text: String = picks.iter().map(|&i| format!("{}\n", LINES[i])).collect();
        drive(TextSource::new(text), bd, 1_000);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, ..ProptestConfig::default() })]

    /// The same program from a file and from memory: the same blocks, the same end.
    #[test]
    fn file_and_text_agree_on_random_programs(
        picks in proptest::collection::vec(0..LINES.len(), 0..60), raw in any::<bool>()
    ) {
        let text: String = picks.iter().map(|&i| format!("{}\n", LINES[i])).collect();
        let bytes = if raw { text.clone().into_bytes() } else { text.replace('\n', "\r\n").into_bytes() };
        let path = std::env::temp_dir()
            .join(format!("mc-reader-prop-{}-{}.ngc", std::process::id(), picks.len()));
        std::fs::write(&path, &bytes).unwrap();
        let mut a = Reader::new(FileSource::open(&path).unwrap(), false);
        a.max_passes = 1_000;
        a.max_reread = 20_000;
        let from_file = collect(a);
        std::fs::remove_file(&path).ok();
        let mut b = Reader::new(TextSource::new(String::from_utf8(bytes).unwrap()), false);
        b.max_passes = 1_000;
        b.max_reread = 20_000;
        let from_text = collect(b);
        prop_assert_eq!(from_file, from_text);
    }
}
