//! Unit tests of `model::equations::parse` (`src/model/equations/parse.rs`).

use isola::model::equations::parse::*;

fn num(v: f64) -> Box<Ast> {
    Box::new(Ast::Num(v))
}

#[test]
fn precedence_follows_the_usual_rules() {
    // -2^2 is −4, 2^3^2 is 2^9, 1 - 2 - 3 is (1 − 2) − 3
    assert_eq!(
        parse("-2^2").unwrap(),
        Ast::Neg(Box::new(Ast::Bin(BinOp::Pow, num(2.0), num(2.0))))
    );
    assert_eq!(
        parse("2^3^2").unwrap(),
        Ast::Bin(
            BinOp::Pow,
            num(2.0),
            Box::new(Ast::Bin(BinOp::Pow, num(3.0), num(2.0)))
        )
    );
    assert_eq!(
        parse("1 - 2 - 3").unwrap(),
        Ast::Bin(
            BinOp::Sub,
            Box::new(Ast::Bin(BinOp::Sub, num(1.0), num(2.0))),
            num(3.0)
        )
    );
    assert_eq!(parse("2**-1e-3").unwrap(), parse("2^(-0.001)").unwrap());
}

#[test]
fn errors_name_the_token_and_its_place() {
    let e = parse("a + * b").unwrap_err();
    assert_eq!((e.token.as_str(), e.span.start), ("*", 4));
    let e = parse("max(a, b").unwrap_err();
    assert_eq!((e.token.as_str(), e.span.start), ("", 8));
    let e = parse("a $ b").unwrap_err();
    assert_eq!((e.token.as_str(), e.span.start), ("$", 2));
    let e = parse("(a + b) c").unwrap_err();
    assert_eq!((e.token.as_str(), e.span.start), ("c", 8));
    assert!(parse("").is_err());
}
