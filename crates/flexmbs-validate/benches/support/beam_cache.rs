//! What the contact benches share: mode-count lists from the environment and a cache of the
//! reduced beam (the reduced-body file and the consistent mass matrix) between runs.

use flexmbs_validate::point_mass_on_beam::Beam;
use std::io::{Read, Write};
use std::path::Path;

/// The comma-separated numbers of the environment variable `name`, or `default`.
pub fn env_list(name: &str, default: &[usize]) -> Vec<usize> {
    match std::env::var(name) {
        Ok(s) => s.split(',').filter_map(|x| x.trim().parse().ok()).collect(),
        Err(_) => default.to_vec(),
    }
}

/// The consistent mass matrix as `n`, `nnz`, column pointers, row indices, values (u64/f64 LE).
fn write_mass(path: &Path, m: &flexmbs_fe::SparseMatrix) {
    let mut f = std::fs::File::create(path).expect("mass file");
    let (ptr, idx, val) = (m.col_ptr(), m.row_idx(), m.val());
    let mut put = |x: u64| f.write_all(&x.to_le_bytes()).expect("write");
    put(m.nrows() as u64);
    put(val.len() as u64);
    ptr.iter().chain(idx).for_each(|&x| put(x as u64));
    for x in val {
        f.write_all(&x.to_le_bytes()).expect("write");
    }
}

/// The matrix [`write_mass`] wrote.
fn read_mass(path: &Path) -> flexmbs_fe::SparseMatrix {
    let mut bytes = vec![];
    std::fs::File::open(path)
        .expect("mass file")
        .read_to_end(&mut bytes)
        .expect("read");
    let word = |i: usize| u64::from_le_bytes(bytes[8 * i..8 * i + 8].try_into().unwrap());
    let (n, nnz) = (word(0) as usize, word(1) as usize);
    let ptr: Vec<usize> = (0..=n).map(|i| word(2 + i) as usize).collect();
    let idx: Vec<usize> = (0..nnz).map(|i| word(3 + n + i) as usize).collect();
    let val: Vec<f64> = (0..nnz)
        .map(|i| f64::from_bits(word(3 + n + nnz + i)))
        .collect();
    let sym = faer::sparse::SymbolicSparseColMat::new_checked(n, n, ptr, None, idx);
    faer::sparse::SparseColMat::new(sym, val)
}

/// The reduced beam of `reduce`, kept in the folder named by the environment variable
/// `cache_var` (`beam.h5` and `mass.bin`) and read from there when it holds one.
pub fn cached_beam<E: std::fmt::Debug>(
    cache_var: &str,
    reduce: impl FnOnce() -> Result<Beam, E>,
) -> Beam {
    let Ok(dir) = std::env::var(cache_var) else {
        return reduce().expect("beam");
    };
    let dir = Path::new(&dir);
    let (body, mass) = (dir.join("beam.h5"), dir.join("mass.bin"));
    if body.exists() && mass.exists() {
        return Beam {
            reduced: flexmbs_io::body_file::read_body(&body).expect("cached beam"),
            mass: read_mass(&mass),
        };
    }
    let beam = reduce().expect("beam");
    std::fs::create_dir_all(dir).expect("cache dir");
    flexmbs_io::body_file::write_body(&body, &beam.reduced).expect("write beam");
    write_mass(&mass, &beam.mass);
    beam
}
