//! Drift check: the committed `docs/registers.md` must be exactly what the generator
//! makes from the committed `shared/registers.def`.

use std::path::Path;

#[test]
fn committed_register_doc_matches_generator() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let def_text = std::fs::read_to_string(root.join(regdef::DEF_PATH)).unwrap();
    let def = regdef::parse(&def_text).unwrap_or_else(|e| panic!("{}: {e}", regdef::DEF_PATH));
    let expected = regdef::generate_markdown(&def);
    let committed = std::fs::read_to_string(root.join(regdef::DOC_PATH)).unwrap_or_default();
    assert!(
        committed == expected,
        "{} differs from what {} generates: run `{}` and commit the result",
        regdef::DOC_PATH,
        regdef::DEF_PATH,
        regdef::WRITE_DOCS_COMMAND
    );
}
