fn main() {
    for f in std::env::args().skip(1) {
        let src = std::fs::read_to_string(&f).unwrap();
        let mut p = Vec::new();
        let ast = pacer::syntax::parse_powertools(&src, &mut p);
        println!("{f}: {} stmts, {} problems {:?}", ast.body.len(), p.len(), p);
    }
}
