//! The controller files shipped in docs/rig/examples load and give a 4-in, 1-out controller.

#[test]
fn every_example_controller_file_loads() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/rig/examples");
    let mut n = 0;
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            let l = pendulab_rig::config::load(&text)
                .unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            assert_eq!(
                (l.controller.ny(), l.controller.nu()),
                (4, 1),
                "{}",
                p.display()
            );
            n += 1;
        }
    }
    assert_eq!(n, 5);
}
