//! The reader against LinuxCNC's documented behaviour: values with known answers, lines,
//! parameters, O-word control flow, errors and their lines, and the two sources.

use super::*;

/// Every block of `src` (block delete as given), or the first error, with the parameters at
/// the end.
fn read_with(src: &str, block_delete: bool, params: &mut Params) -> Result<Vec<Block>, GcodeError> {
    let mut r = Reader::new(TextSource::new(src.to_string()), block_delete);
    let mut out = Vec::new();
    while let Some(b) = r.next_block(params)? {
        out.push(b);
        assert!(out.len() < 100_000, "runaway program");
    }
    Ok(out)
}

fn read(src: &str) -> Vec<Block> {
    read_with(src, false, &mut Params::new()).unwrap_or_else(|e| panic!("{e}"))
}

fn error(src: &str) -> GcodeError {
    match read_with(src, false, &mut Params::new()) {
        Ok(b) => panic!("{src:?}: no error; blocks {b:?}"),
        Err(e) => e,
    }
}

/// The X values of the blocks.
fn xs(src: &str) -> Vec<f64> {
    read(src)
        .iter()
        .map(|b| b.word('X').unwrap_or(f64::NAN))
        .collect()
}

/// The value of `value` (anything that may follow a word letter).
fn eval(value: &str) -> f64 {
    let b = read(&format!("X{value}"));
    assert_eq!(b.len(), 1);
    b[0].word('X').unwrap()
}

fn eval_err(value: &str) -> String {
    error(&format!("X{value}")).message
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol
}

#[test]
fn expressions_give_linuxcncs_answers() {
    // Values from LinuxCNC's expression test program and manual.
    let cases: &[(&str, f64, f64)] = &[
        ("[1 + 2]", 3.0, 0.0),
        ("[1 - 2]", -1.0, 0.0),
        ("[1 --3]", 4.0, 0.0),
        ("[2/5]", 0.4, 1e-15),
        ("[3.0 * 5]", 15.0, 0.0),
        ("[0 OR 0]", 0.0, 0.0),
        ("[0 OR 1]", 1.0, 0.0),
        ("[2 or 2]", 1.0, 0.0),
        ("[0 AND 1]", 0.0, 0.0),
        ("[2 and 2]", 1.0, 0.0),
        ("[0 XOR 1]", 1.0, 0.0),
        ("[2 xor 2]", 0.0, 0.0),
        ("[15 MOD 4.0]", 3.0, 0.0),
        ("[1 + 2 * 3 - 4 / 5]", 6.2, 1e-12),
        ("[2.0 / 3 * 1.5 - 5.5 / 11.0]", 0.5, 1e-12),
        ("sin[30]", 0.5, 1e-12),
        ("cos[0.0]", 1.0, 0.0),
        ("tan[60.0]", 1.7321, 1e-4),
        ("sqrt[3]", 1.7321, 1e-4),
        ("atan[1.7321]/[1.0]", 60.0, 1e-3),
        ("asin[1.0]", 90.0, 1e-12),
        ("acos[0.707107]", 45.0, 1e-4),
        ("abs[-1.23]", 1.23, 0.0),
        ("round[-0.499]", 0.0, 0.0),
        ("round[-0.5001]", -1.0, 0.0),
        ("round[2.444]", 2.0, 0.0),
        ("round[9.975]", 10.0, 0.0),
        ("fix[-0.499]", -1.0, 0.0),
        ("fix[-0.5001]", -1.0, 0.0),
        ("fix[9.975]", 9.0, 0.0),
        ("fup[-0.499]", 0.0, 0.0),
        ("fup[-0.5001]", 0.0, 0.0),
        ("fup[2.444]", 3.0, 0.0),
        ("exp[2.3026]", 10.0, 1e-3),
        ("ln[10]", std::f64::consts::LN_10, 1e-15),
        // Left to right within a level, `**` included: [2**3]**2.
        ("[2 ** 3 ** 2]", 64.0, 0.0),
        ("[2 * 3 ** 2]", 18.0, 0.0),
        // A sign binds tighter than `**`.
        ("[-2 ** 2]", 4.0, 0.0),
        ("-[2 ** 2]", -4.0, 0.0),
        // MOD is never negative (LinuxCNC adds |b| to fmod's negative result).
        ("[-7 MOD 3]", 2.0, 0.0),
        ("[7 MOD -3]", 1.0, 0.0),
        ("[-7 MOD -3]", 2.0, 0.0),
        // Relational below arithmetic, logical below relational.
        ("[1 + 1 EQ 2]", 1.0, 0.0),
        ("[1 LT 2 AND 3 GT 4]", 0.0, 0.0),
        ("[1 LT 2 OR 3 GT 4]", 1.0, 0.0),
        ("[3 GE 3]", 1.0, 0.0),
        ("[3 LE 2.9]", 0.0, 0.0),
        ("[2 NE 2]", 0.0, 0.0),
        // EQ with LinuxCNC's tolerance of 1e-6.
        ("[1 EQ 1.0000005]", 1.0, 0.0),
        ("[1 EQ 1.000002]", 0.0, 0.0),
        ("[1 NE 1.0000005]", 0.0, 0.0),
        ("[1 GE 1.0000005]", 1.0, 0.0),
        ("[1 GT 1.0000005]", 0.0, 0.0),
        // ATAN's quadrants, in degrees.
        ("atan[1]/[1]", 45.0, 1e-12),
        ("atan[1]/[-1]", 135.0, 1e-12),
        ("atan[-1]/[-1]", -135.0, 1e-12),
        ("atan[-1]/[1]", -45.0, 1e-12),
        ("atan[1]/[0]", 90.0, 1e-12),
        // Numbers.
        ("1.", 1.0, 0.0),
        (".5", 0.5, 0.0),
        ("-0.25", -0.25, 0.0),
        ("+3", 3.0, 0.0),
        // A sign before a sign is a signed value: -(-1).
        ("--1", 1.0, 0.0),
        ("-[1+1]", -2.0, 0.0),
        ("[[[1]]]", 1.0, 0.0),
        ("ABS[ - 2 ]", 2.0, 0.0),
    ];
    for &(text, want, tol) in cases {
        let got = eval(text);
        assert!(close(got, want, tol), "{text} = {got}, want {want}");
    }
}

#[test]
fn linuxcncs_manual_example_with_a_parameter() {
    // `[1 + acos[0] - [#3 ** [4.0/2]]]` with #3 = 2: 1 + 90 - 4.
    let b = read("#3=2\nX[ 1 + acos[0] - [#3 ** [4.0/2]]]");
    assert!(close(b[0].word('X').unwrap(), 87.0, 1e-12));
}

#[test]
fn domain_errors_name_their_line() {
    for (v, what) in [
        ("sqrt[-1]", "SQRT"),
        ("ln[0]", "LN"),
        ("ln[-2]", "LN"),
        ("[1/0]", "division by zero"),
        ("[1/[2-2]]", "division by zero"),
        ("acos[1.5]", "ACOS"),
        ("asin[-1.0001]", "ASIN"),
        ("[1 MOD 0]", "MOD"),
        ("[-8 ** 0.5]", "power"),
        ("[10 ** 400]", "infinity"),
        ("exp[1000]", "infinity"),
    ] {
        let e = eval_err(v);
        assert!(e.contains(what), "{v}: {e}");
    }
    let e = error("G0 X1\n\nG1 X[2 / 0]\n");
    assert_eq!(e.line, 3);
    assert!(e.message.contains("division by zero"), "{e}");
}

#[test]
fn malformed_values_are_errors() {
    for v in [
        "[1 + 2",
        "[1 2 +]",
        "[1 FOO 2]",
        "foo[1]",
        "sin 30",
        "atan[1]",
        "atan[1]/2",
        "1.2.3",
        ".",
        "",
        "[]",
        "#",
        "#0",
        "#5603",
        "#1.5",
        "#<nope>",
        "#<>",
        "#<open",
        "exists[1]",
        "exists[#<a>+1]",
    ] {
        let e = error(&format!("G1 X{v}"));
        assert_eq!(e.line, 1, "{v}");
    }
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let deep = format!("X{}1{}", "[".repeat(30_000), "]".repeat(30_000));
    assert!(error(&deep).message.contains("nested"));
    let signs = format!("X{}1", "-+".repeat(30_000));
    assert!(error(&signs).message.contains("nested"));
    let hashes = format!("X{}1", "#".repeat(60_000));
    assert!(error(&hashes).message.contains("nested"));
    // Within the limit it works: #1 = 1, ##1 = #1.
    assert_eq!(eval(&format!("{}2{}", "[".repeat(40), "]".repeat(40))), 2.0);
}

#[test]
fn words_g_and_m_codes() {
    let b = read(
        "n10 g1 G38.2 g0.0 x1 Y-2 z.5 a1 B2 C3 U4 V5 W6 I7 J8 K9 R10 P11 Q12 L13 E14 \
                  H15 D16 F17 S18 T19 m3 M30 M[1+1]",
    );
    let b = &b[0];
    assert_eq!(b.line, 1);
    assert_eq!(b.g, vec![10, 382, 0]);
    assert_eq!(b.m, vec![3, 30, 2]);
    for (l, v) in [
        ('X', 1.0),
        ('Y', -2.0),
        ('Z', 0.5),
        ('A', 1.0),
        ('W', 6.0),
        ('E', 14.0),
        ('T', 19.0),
    ] {
        assert_eq!(b.word(l), Some(v), "{l}");
    }
    assert_eq!(b.word('N'), None);
    assert_eq!(b.word('G'), None);
    assert_eq!(b.word('M'), None);
    assert_eq!(read("G[59.3]")[0].g, vec![593]);
    assert_eq!(
        read("#1=6.1\nG#1 G[#1*10-1] G 4 1 . 1")[0].g,
        vec![61, 600, 411]
    );
    assert_eq!(read("G0.9999999")[0].g, vec![10]);
    for bad in [
        "G1.25", "G-1", "G100", "M1.5", "M-3", "X1 X2", "G1 N10", "G1 O100", "G1 $1", "G1 X1 ?",
    ] {
        assert_eq!(error(bad).line, 1, "{bad}");
    }
    assert!(error("X1 y2 x3").message.contains("two X words"));
}

#[test]
fn lines_comments_and_case() {
    let b = read("G1X1 (a comment) y2 ; x9\n(only a comment)\n  \t \n;semicolon\ng0\tX 1 2 . 5");
    assert_eq!(b.len(), 2);
    assert_eq!((b[0].word('X'), b[0].word('Y')), (Some(1.0), Some(2.0)));
    assert_eq!(
        b[1].word('X'),
        Some(12.5),
        "blanks inside a number are ignored"
    );
    assert_eq!(b[1].line, 5);
    assert_eq!(error("G1\nG1 (open\n").line, 2);
    assert_eq!(error("G1 (a (b) c)").line, 1);
    assert_eq!(read("G1 X1\r\nG0 X2\r\n").len(), 2, "CR LF line ends");
}

#[test]
fn block_delete_on_and_off() {
    let src = "G0 X1\n/G0 X2\n  / G0 X3\nG0 X4 (/ not a delete)\n";
    let on = read_with(src, true, &mut Params::new()).unwrap();
    assert_eq!(
        on.iter().map(|b| b.word('X').unwrap()).collect::<Vec<_>>(),
        vec![1.0, 4.0]
    );
    let off = read_with(src, false, &mut Params::new()).unwrap();
    assert_eq!(
        off.iter().map(|b| b.word('X').unwrap()).collect::<Vec<_>>(),
        vec![1.0, 2.0, 3.0, 4.0]
    );
    // Block delete skips settings too.
    let mut p = Params::new();
    read_with("/#1=5\n", true, &mut p).unwrap();
    assert_eq!(p.get(1), Some(0.0));
}

#[test]
fn percent_brackets_the_program() {
    assert_eq!(xs("\n%\nX1\n%\nX2\n"), vec![1.0]);
    assert_eq!(xs(" % \nX1\nX2"), vec![1.0, 2.0], "end of text ends it too");
    assert_eq!(
        xs("X1\n%\nX2"),
        vec![1.0],
        "a % after code ends the program"
    );
    assert_eq!(error("%\nX1 %\n").line, 2);
    // Nothing after the closing % is read, errors included.
    assert_eq!(xs("%\nX1\n%\nG1 X[1/0]\n"), vec![1.0]);
}

#[test]
fn messages_with_parameters_substituted() {
    let b = read("#1=2.5 #<len>=10\n(MSG, Length #<len> at #1)\nG0 X1 (PRINT,x=#1)\n(DEBUG,%d#<len>)\n(just a comment #1)");
    assert_eq!(b.len(), 3);
    assert_eq!(
        b[0].message.as_deref(),
        Some(" Length 10.000000 at 2.500000")
    );
    assert!(b[0].words.iter().all(Option::is_none) && b[0].g.is_empty());
    assert_eq!(b[1].message.as_deref(), Some("x=2.500000"));
    assert_eq!(b[1].word('X'), Some(1.0));
    assert_eq!(b[2].message.as_deref(), Some("10"));
    // The line's own settings are applied before its message is formatted (as LinuxCNC,
    // which stores parameters before running the block's comment).
    let b = read("#1=1\n#1=7 (msg,#1)");
    assert_eq!(b[0].message.as_deref(), Some("7.000000"));
}

#[test]
fn settings_on_a_line_use_the_values_from_before_it() {
    let mut p = Params::new();
    let b = read_with(
        "#1=1 #2=2 #3=3\n#3=15 #4=[#3+1] X#3 Y#4\n#1=[#1+1] #1=[#1+5]\n",
        false,
        &mut p,
    )
    .unwrap();
    assert_eq!((b[0].word('X'), b[0].word('Y')), (Some(3.0), Some(0.0)));
    assert_eq!(p.get(3), Some(15.0));
    assert_eq!(p.get(4), Some(4.0));
    assert_eq!(
        p.get(1),
        Some(6.0),
        "the last setting of #1 wins, from the old value"
    );
    // Indirect: ##1 reads the parameter whose number #1 holds; #[..] computes the number.
    let b = read("#1=7 #7=42\n#[1+2]=3 X##1 Y#[3*2+1]\nZ#3");
    assert_eq!((b[0].word('X'), b[0].word('Y')), (Some(42.0), Some(42.0)));
    assert_eq!(b[1].word('Z'), Some(3.0));
}

#[test]
fn named_parameters() {
    let b = read("#<My Var>=3 #<_glob>=4\nX#<myvar> Y#< MYVAR > Z#<_GLOB> A#99");
    assert_eq!(b[0].word('X'), Some(3.0));
    assert_eq!(b[0].word('Y'), Some(3.0));
    assert_eq!(b[0].word('Z'), Some(4.0));
    assert_eq!(b[0].word('A'), Some(0.0));
    let e = error("G0\n#<x>=1 X#<x>\n");
    assert_eq!(e.line, 2, "a name set on a line is not yet set on it");
    assert!(e.message.contains("#<x>"), "{e}");
    assert_eq!(eval("exists[#<nope>]"), 0.0);
    // LinuxCNC's exists test: a numbered parameter exists when in range.
    let b = read(
        "#<a>=999\nG0 X EXISTS[#1] Y EXISTS[#99999] Z EXISTS[#<a>] A EXISTS[#<b>]\n\
                  #1=2\n#2=99999\nG0 X EXISTS[##1] Y EXISTS[##2] Z EXISTS[###1]",
    );
    let got: Vec<_> = b
        .iter()
        .map(|b| [b.word('X'), b.word('Y'), b.word('Z'), b.word('A')])
        .collect();
    assert_eq!(
        got,
        vec![
            [Some(1.0), Some(0.0), Some(1.0), Some(0.0)],
            [Some(1.0), Some(0.0), Some(0.0), None]
        ]
    );
    assert_eq!(read("#<a>=0\nX EXISTS[#<A>]")[0].word('X'), Some(1.0));
    assert_eq!(error("#5603=1").line, 1);
    assert_eq!(error("#0=1").line, 1);
    assert_eq!(error("#1 2").line, 1, "a setting without '='");
}

#[test]
fn subroutine_restores_its_callers_parameters_and_drops_its_locals() {
    let src = "\
o100 sub
  #<local> = [#1 * 2]
  G1 X#1 Y#2 Z#<local>
  #1 = 99
o100 endsub
#1 = 5
#<local> = -1
o100 call [10] [20]
G0 X#1 Y#<local>
";
    let b = read(src);
    assert_eq!(b.len(), 2);
    assert_eq!(b[0].line, 3);
    assert_eq!(
        (b[0].word('X'), b[0].word('Y'), b[0].word('Z')),
        (Some(10.0), Some(20.0), Some(20.0))
    );
    assert_eq!(b[1].line, 9);
    assert_eq!((b[1].word('X'), b[1].word('Y')), (Some(5.0), Some(-1.0)));
}

#[test]
fn a_named_local_is_not_visible_after_return() {
    let src = "o<s> sub\n#<inner>=1\no<s> endsub\no<s> call\nX#<inner>\n";
    let e = error(src);
    assert_eq!(e.line, 5);
    assert!(e.message.contains("#<inner>"), "{e}");
    // A global is.
    assert_eq!(
        xs("o<s> sub\n#<_g>=7\no<s> endsub\no<s> call\nX#<_g>\n"),
        vec![7.0]
    );
}

#[test]
fn subroutine_called_before_its_definition() {
    let src = "\
%
o<later> call [3]
G0 X#<_value>
o<later> call [4]
G0 X#<_value>
M2
o<later> sub
  G1 X#1
  o<later> return [#1 * 10]
  G1 X-1 (never)
o<later> endsub
%
";
    let b = read(src);
    let got: Vec<(usize, Option<f64>)> = b.iter().map(|b| (b.line, b.word('X'))).collect();
    assert_eq!(
        got,
        vec![
            (8, Some(3.0)),
            (3, Some(30.0)),
            (8, Some(4.0)),
            (5, Some(40.0)),
            (6, None)
        ]
    );
    assert_eq!(
        b[4].m,
        vec![2],
        "M2 is the interpreter's: the reader reads on past it"
    );
}

#[test]
fn return_values() {
    let mut p = Params::new();
    let src = "\
o1 sub
o1 endsub [2.5]
o2 sub
o2 endsub
o1 call
#10 = #<_value>
#11 = #<_value_returned>
o2 call
#12 = #<_value>
#13 = #<_value_returned>
";
    read_with(src, false, &mut p).unwrap();
    assert_eq!(
        [p.get(10), p.get(11), p.get(12), p.get(13)],
        [Some(2.5), Some(1.0), Some(0.0), Some(0.0)]
    );
    // Defined (0) before any call; `return` may carry an enclosing construct's label
    // (LinuxCNC's retval example).
    let src = "\
X#<_value> Y#<_value_returned>
o1000 sub
o1010 if [#1 GT 0]
o1010    return [123*[#1]]
o1010 endif
o1000 endsub [4712]
o1000 call [2]
X#<_value>
o1000 call [-2]
X#<_value>
";
    assert_eq!(xs(src), vec![0.0, 246.0, 4712.0]);
}

#[test]
fn recursion_and_its_depth_limit() {
    // Factorial by recursion, a result through #<_value>.
    let src = "\
o<fact> sub
  o1 if [#1 LE 1]
    o<fact> return [1]
  o1 endif
  o<fact> call [#1 - 1]
  o<fact> return [#1 * #<_value>]
o<fact> endsub
o<fact> call [5]
X#<_value>
";
    assert_eq!(xs(src), vec![120.0]);
    let e = error("o1 sub\no1 call\no1 endsub\no1 call\n");
    assert!(e.message.contains("deeper"), "{e}");
    assert_eq!(e.line, 2);
}

#[test]
fn while_loop_gives_n_blocks() {
    let src = "#1=0\no101 while [#1 LT 5]\n  G1 X#1\n  #1=[#1+1]\no101 endwhile\nG0 X-1\n";
    let b = read(src);
    assert_eq!(
        b.iter().map(|b| b.word('X').unwrap()).collect::<Vec<_>>(),
        vec![0.0, 1.0, 2.0, 3.0, 4.0, -1.0]
    );
    assert!(b[..5].iter().all(|b| b.line == 3));
    assert_eq!(b[5].line, 6);
    // A false condition skips the body without evaluating it.
    assert_eq!(xs("o1 while [0]\nX[1/0]\no1 endwhile\nX2"), vec![2.0]);
}

#[test]
fn do_while_runs_once_when_false() {
    assert_eq!(xs("o1 do\nX1\no1 while [0]\nX2\n"), vec![1.0, 2.0]);
    let src = "#1=3\no1 do\nX#1\n#1=[#1-1]\no1 while [#1 GT 0]\n";
    assert_eq!(xs(src), vec![3.0, 2.0, 1.0]);
}

#[test]
fn repeat_runs_n_times() {
    assert_eq!(
        xs("#1=0\no1 repeat [3]\n#1=[#1+1]\nX#1\no1 endrepeat\n"),
        vec![1.0, 2.0, 3.0]
    );
    assert_eq!(xs("o1 repeat [0]\nX1\no1 endrepeat\nX2"), vec![2.0]);
    assert_eq!(
        xs("o1 repeat [2.6]\nX1\no1 endrepeat"),
        vec![1.0; 3],
        "the count is rounded"
    );
    // Nested repeats.
    assert_eq!(
        xs("o1 repeat [2]\no2 repeat [3]\nX1\no2 endrepeat\no1 endrepeat").len(),
        6
    );
}

#[test]
fn break_and_continue() {
    let src = "\
#1=0
o1 while [1]
  #1=[#1+1]
  o2 if [#1 EQ 2]
    o1 continue
  o2 endif
  o3 if [#1 GT 4]
    o1 break
  o3 endif
  X#1
o1 endwhile
Y#1
";
    let b = read(src);
    let got: Vec<_> = b.iter().map(|b| (b.word('X'), b.word('Y'))).collect();
    assert_eq!(
        got,
        vec![
            (Some(1.0), None),
            (Some(3.0), None),
            (Some(4.0), None),
            (None, Some(5.0))
        ]
    );
    // In do-while, continue goes to the condition; in repeat, to the next pass.
    let src =
        "#1=0\no1 do\n#1=[#1+1]\no2 if [#1 LT 3]\no1 continue\no2 endif\nX#1\no1 while [#1 LT 4]";
    assert_eq!(xs(src), vec![3.0, 4.0]);
    let src =
        "#1=0\no1 repeat [4]\n#1=[#1+1]\no2 if [#1 EQ 2]\no1 continue\no2 endif\nX#1\no1 endrepeat";
    assert_eq!(xs(src), vec![1.0, 3.0, 4.0]);
    let src = "o1 do\nX1\no1 break\nX2\no1 while [1]\nX3";
    assert_eq!(xs(src), vec![1.0, 3.0]);
}

#[test]
fn nested_ifs_and_else_chains() {
    let pick = |v: f64| {
        let src = format!(
            "#1={v}
o1 if [#1 LT 0]
  X-1
o1 elseif [#1 EQ 0]
  X0
o1 elseif [#1 LT 10]
  o2 if [#1 LT 5]
    X1
  o2 else
    X5
  o2 endif
o1 else
  X10
  o3 if [1]
    Y1
  o3 endif
o1 endif
Z0
"
        );
        read(&src)
            .iter()
            .map(|b| (b.word('X'), b.word('Y')))
            .collect::<Vec<_>>()
    };
    assert_eq!(pick(-3.0), vec![(Some(-1.0), None), (None, None)]);
    assert_eq!(pick(0.0), vec![(Some(0.0), None), (None, None)]);
    assert_eq!(pick(2.0), vec![(Some(1.0), None), (None, None)]);
    assert_eq!(pick(7.0), vec![(Some(5.0), None), (None, None)]);
    assert_eq!(
        pick(12.0),
        vec![(Some(10.0), None), (None, Some(1.0)), (None, None)]
    );
    // Skipped branches are not evaluated; an elseif after a taken branch is not either.
    assert_eq!(
        xs("o1 if [1]\nX1\no1 elseif [#<undefined>]\nX2\no1 else\nX3\no1 endif"),
        vec![1.0]
    );
}

#[test]
fn mismatched_and_unterminated_constructs_name_their_lines() {
    let cases: &[(&str, usize)] = &[
        ("G0\no1 if [1]\nX1\n", 2),
        ("o1 if [0]\nX1\n", 1),
        ("o1 while [1]\nX1\no2 endwhile\n", 3),
        ("X1\no1 endif\n", 2),
        ("o1 if [1]\no1 endwhile\n", 2),
        ("o1 if [0]\no1 else\no1 elseif [1]\no1 endif", 3),
        ("o1 if [0]\no1 else\no1 else\no1 endif", 3),
        ("o1 do\nX1\n", 1),
        ("o1 repeat [2]\nX1\n", 1),
        ("G0\no1 break\n", 2),
        ("o1 while [1]\nX1\no2 continue\no1 endwhile", 3),
        ("o1 sub\nX1\n", 1),
        ("o1 endsub\n", 1),
        ("o1 return\n", 1),
        ("G0\n\no9 call\n", 3),
        ("o1 sub\no2 endsub\no1 endsub\no1 call\n", 2),
        ("o1 sub\no2 if [1]\no1 endsub\no1 call\n", 2),
        ("o1 if [1]\no2 sub\no2 endsub\no1 endif\n", 2),
        ("o1 if [1]\no1 if [1]\no1 endif\no1 endif\n", 2),
        ("o1 foo\n", 1),
        ("o\n", 1),
        ("o<x\n", 1),
        ("o1 if\n", 1),
        ("o1 if 1\n", 1),
        ("o1 if [1] X1\n", 1),
        ("o1 endif [1]\n", 1),
        ("o1 sub\no1 endsub\no1 sub\no1 endsub\n", 3),
        ("o1 call [1] X2\no1 sub\no1 endsub", 1),
    ];
    for &(src, line) in cases {
        let e = error(src);
        assert_eq!(e.line, line, "{src:?}: {e}");
    }
}

#[test]
fn labels_are_local_to_a_call() {
    // The sub's o1 is not the caller's o1.
    let src = "\
o<s> sub
  o1 repeat [2]
    X1
  o1 endrepeat
o<s> endsub
o1 repeat [2]
  o<s> call
o1 endrepeat
";
    assert_eq!(xs(src).len(), 4);
    // break in a sub cannot leave the caller's loop.
    let e = error("o<s> sub\no1 break\no<s> endsub\no1 while [1]\no<s> call\no1 endwhile\n");
    assert_eq!(e.line, 2);
}

#[test]
fn a_loop_without_blocks_is_stopped() {
    let mut p = Params::new();
    let e = read_with("G0\no1 while [1]\n#1=[#1+1]\no1 endwhile\n", false, &mut p).unwrap_err();
    assert!(e.message.contains("1000000"), "{e}");
    assert_eq!(e.line, 4);
    assert_eq!(
        p.get(1),
        Some(1_000_001.0),
        "the pass over the limit is refused"
    );
    // Long bodies and subroutines calling each other are held by the count of lines read
    // again: 2^40 calls without a block would otherwise run for days.
    let src = "\
o1 sub
o2 if [#1 LT 40]
o1 call [#1 + 1]
o1 call [#1 + 1]
o2 endif
o1 endsub
G0
o1 call [0]
";
    let mut r = Reader::new(TextSource::new(src.into()), false);
    r.max_reread = 200_000;
    let mut p = Params::new();
    assert!(r.next_block(&mut p).unwrap().is_some());
    let e = r.next_block(&mut p).unwrap_err();
    assert!(e.message.contains("200000 lines"), "{e}");
    // A loop giving blocks goes on as long as its consumer reads.
    let mut r = Reader::new(
        TextSource::new("o1 while [1]\nX1\no1 endwhile\n".into()),
        false,
    );
    let mut p = Params::new();
    for _ in 0..2_000 {
        assert!(r.next_block(&mut p).unwrap().is_some());
    }
}

#[test]
fn after_an_error_or_the_end_nothing_follows() {
    let mut r = Reader::new(TextSource::new("X1\nX[1/0]\nX3\n".into()), false);
    let mut p = Params::new();
    assert!(r.next_block(&mut p).unwrap().is_some());
    assert_eq!(r.next_block(&mut p).unwrap_err().line, 2);
    assert_eq!(r.line(), 2);
    assert_eq!(r.next_block(&mut p), Ok(None));
}

#[test]
fn long_lines_and_bad_text() {
    let long = format!("X1\nX2 ({})\nX3\n", "a".repeat(MAX_LINE_BYTES));
    let e = error(&long);
    assert_eq!(e.line, 2);
    assert!(e.message.contains("longer"), "{e}");
    let ok = format!("X1 ({})\n", "a".repeat(MAX_LINE_BYTES - 10));
    assert_eq!(xs(&ok), vec![1.0]);
    assert_eq!(
        error("X1\nX\u{e9}\n").line,
        2,
        "a non-ASCII letter is not a word"
    );
    assert_eq!(
        xs("X1 (caf\u{e9} \u{1f600})\n"),
        vec![1.0],
        "any text in comments"
    );
}

/// A unique scratch file holding `bytes`.
fn temp_file(tag: &str, bytes: &[u8]) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("mc-reader-{}-{tag}.ngc", std::process::id()));
    std::fs::write(&path, bytes).unwrap();
    path
}

fn file_blocks(path: &std::path::Path) -> Result<Vec<Block>, GcodeError> {
    let mut r = Reader::new(FileSource::open(path).unwrap(), false);
    let mut p = Params::new();
    let mut out = Vec::new();
    while let Some(b) = r.next_block(&mut p)? {
        out.push(b);
    }
    Ok(out)
}

#[test]
fn file_and_text_sources_give_the_same_blocks() {
    // Long enough that loops and calls go back across BufReader's 8 KiB buffer.
    let mut src = String::from("%\n(MSG, start)\no<far> call [2]\n#1=0\no1 while [#1 LT 3]\n");
    for i in 0..400 {
        src.push_str(&format!("  G1 X[#1 + {i}] (padding padding padding)\n"));
    }
    src.push_str(
        "  o2 repeat [2]\n    o<far> call [#1]\n  o2 endrepeat\n  #1=[#1+1]\no1 endwhile\nM2\n",
    );
    for i in 0..300 {
        src.push_str(&format!(
            "(filler {i} ........................................)\n"
        ));
    }
    src.push_str("o<far> sub\n  G0 Y#1\no<far> endsub\n%\n");
    let text = read(&src);
    assert_eq!(text.len(), 2 + 3 * (400 + 2) + 1);
    let path = temp_file("same", src.as_bytes());
    let file = file_blocks(&path).unwrap();
    std::fs::remove_file(&path).ok();
    assert_eq!(file, text);
}

#[test]
fn file_source_limits_lines_and_checks_utf8() {
    let mut bytes = b"X1\nX2 (".to_vec();
    bytes.extend(vec![b'a'; 3 * MAX_LINE_BYTES]);
    bytes.extend_from_slice(b")\nX3\n");
    let path = temp_file("long", &bytes);
    let e = file_blocks(&path).unwrap_err();
    std::fs::remove_file(&path).ok();
    assert_eq!(e.line, 2);
    let path = temp_file("utf8", b"X1\r\nX2 (\xff)\r\n");
    let e = file_blocks(&path).unwrap_err();
    std::fs::remove_file(&path).ok();
    assert_eq!(e.line, 2);
    assert!(e.message.contains("UTF-8"), "{e}");
    // The line after a too-long one is read (the source skipped the rest of it).
    let path = temp_file("skip", &bytes);
    let mut s = FileSource::open(&path).unwrap();
    let mut buf = String::new();
    assert!(s.read_line(&mut buf).unwrap());
    assert!(s.read_line(&mut buf).is_err());
    assert!(s.read_line(&mut buf).unwrap());
    assert_eq!(buf, "X3");
    assert_eq!(s.tell(), bytes.len() as u64);
    assert!(!s.read_line(&mut buf).unwrap());
    std::fs::remove_file(&path).ok();
}

#[test]
fn text_source_positions() {
    let mut s = TextSource::new("ab\n\u{e9}\nlast".into());
    let mut buf = String::new();
    assert!(s.read_line(&mut buf).unwrap());
    let p = s.tell();
    assert_eq!(p, 3);
    assert!(s.read_line(&mut buf).unwrap());
    assert_eq!(buf, "\u{e9}");
    assert!(s.read_line(&mut buf).unwrap());
    assert_eq!(buf, "last");
    assert!(!s.read_line(&mut buf).unwrap());
    s.seek(p).unwrap();
    assert!(s.read_line(&mut buf).unwrap());
    assert_eq!(buf, "\u{e9}");
    assert!(s.seek(4).is_err(), "inside a character");
    assert!(s.seek(100).is_err());
}
