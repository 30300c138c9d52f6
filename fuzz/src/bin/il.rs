//! AFL++ target: the Il front end (`plcc check` of one `.il` file).
fn main() {
    afl::fuzz!(|data: &[u8]| {
        plcc_fuzz::check(data, plcc_frontend::Lang::Il, "fuzz.il");
    });
}
