//! Unit tests of `model::equations::graph` (`src/model/equations/graph.rs`).

use isola::model::equations::graph::*;

#[test]
fn shared_subexpressions_are_one_node_and_identities_fold() {
    let mut g = Graph::default();
    let x = g.state(0);
    let a = g.mul(x, x);
    let b = g.mul(x, x);
    assert_eq!(a, b);
    let zero = g.num(0.0);
    let one = g.num(1.0);
    assert_eq!(g.add(a, zero), a);
    assert_eq!(g.mul(one, a), a);
    let two = g.num(2.0);
    let three = g.num(3.0);
    let five = g.add(two, three);
    assert_eq!(g.constant(five), Some(5.0));
}
