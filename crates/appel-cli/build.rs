//! Sets the cfg `shared_data` when the shared test data is there (see the `appel-testdata` crate).

fn main() {
    appel_testdata::build_script();
}
