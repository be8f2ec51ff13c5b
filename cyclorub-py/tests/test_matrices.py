"""Models from arrays: numpy and scipy.sparse matrices give the case a
TOML file with inline matrices gives, and the academic model's matrices
give the academic model's branch."""

import numpy as np
import pytest
import scipy.sparse as sp

import cyclorub

# The paper's academic sector (Table 1; topology of docs/design.md §4): in each
# sector m1-k1-m2-k2-m3-k3-m4, m4-k4-ground, m4-k5-m5, and m5 of sector j
# on k5 to m4 of sector j+1.
MASSES = [0.2, 0.3, 0.4, 1.2, 1.2]
K1, K2, K3, K4, K5 = 2e6, 1e6, 40e6, 0.6e6, 50e6


def academic_matrices():
    """(M0, K0, K1): the block-circulant sector, coupling row: sector j,
    column: sector j+1."""
    mass = np.diag(MASSES)
    stiffness = np.zeros((5, 5))
    for a, b, k in [(0, 1, K1), (1, 2, K2), (2, 3, K3), (3, 4, K5)]:
        stiffness[a, a] += k
        stiffness[b, b] += k
        stiffness[a, b] -= k
        stiffness[b, a] -= k
    stiffness[3, 3] += K4
    # The spring to the next sector: m5 here, m4 there.
    stiffness[4, 4] += K5
    stiffness[3, 3] += K5
    coupling = np.zeros((5, 5))
    coupling[4, 3] = -K5
    return mass, stiffness, coupling


def toml_rows(matrix):
    return "[" + ", ".join("[" + ", ".join(repr(float(v)) for v in row) + "]"
                           for row in np.asarray(matrix)) + "]"


def test_sparse_matrices_equal_the_toml_path():
    mass, stiffness, coupling = academic_matrices()
    text = f"""
[model]
kind = "matrices"
sectors = 24
mass = {toml_rows(mass)}
stiffness = {toml_rows(stiffness)}
stiffness_coupling = {toml_rows(coupling)}
"""
    from_toml = cyclorub.Case.from_toml(text)
    from_sparse = cyclorub.Case.from_matrices(
        sp.csr_matrix(mass), sp.csc_matrix(stiffness), sectors=24,
        couplings=(None, sp.coo_matrix(coupling)))
    from_dense = cyclorub.Case.from_matrices(mass, stiffness, sectors=24,
                                             couplings={"stiffness": coupling})
    assert from_sparse.to_dict() == from_toml.to_dict() == from_dense.to_dict()
    at = [118.0, 124.0, 127.0, 131.0]
    a = from_toml.run(at_hz=at, stability=False, progress=False)
    b = from_sparse.run(at_hz=at, stability=False, progress=False)
    np.testing.assert_array_equal(a.unknowns, b.unknowns)
    np.testing.assert_array_equal(a.amplitude, b.amplitude)


def test_the_academic_matrices_give_the_academic_branch():
    mass, stiffness, coupling = academic_matrices()
    case = cyclorub.Case.from_matrices(sp.csr_matrix(mass), sp.csr_matrix(stiffness),
                                       sectors=24, couplings=(None, sp.csr_matrix(coupling)))
    np.testing.assert_allclose(case.modes()[1], cyclorub.Case.default().modes()[1], rtol=1e-12)
    at = [115.0, 122.0, 126.0, 128.0, 133.0]
    ours = case.run(at_hz=at, stability=False, progress=False)
    paper = cyclorub.Case.default().run(at_hz=at, stability=False, progress=False)
    np.testing.assert_allclose(ours.amplitude, paper.amplitude, rtol=1e-9)


def test_a_finite_element_sector_with_boundaries_and_a_damping_matrix():
    # The academic chain as a finite-element sector: the sector's dofs plus
    # a copy of m4 of the next sector as its right boundary (dof 6), paired
    # with the left boundary m4 (dof 4); the boundary mass is shared.
    mass, stiffness, coupling = academic_matrices()
    n = 6
    m = np.zeros((n, n))
    k = np.zeros((n, n))
    m[:5, :5] = mass
    k[:5, :5] = stiffness
    # m4's spring from the previous sector (m5 there) now sits on dof 6 here.
    k[3, 3] -= K5
    k[5, 5] += K5
    k[4, 5] = k[5, 4] = -K5
    # Mass of m4 split between the two boundary copies.
    m[3, 3] = m[5, 5] = MASSES[3] / 2
    fe = cyclorub.Case.from_matrices(sp.csr_matrix(m), sp.csr_matrix(k), sectors=24,
                                     left_boundary=[4], right_boundary=[6])
    np.testing.assert_allclose(fe.modes()[1], cyclorub.Case.default().modes()[1], rtol=1e-9)
    rayleigh = cyclorub.Case.from_matrices(mass, stiffness, sectors=24, couplings=(None, coupling),
                                           damping={"kind": "rayleigh", "beta": 1e-6})
    assert rayleigh.model.damping.kind == "rayleigh"
    matrix = cyclorub.Case.from_matrices(mass, stiffness, sectors=24, couplings=(None, coupling),
                                         damping=sp.identity(5) * 0.1)
    assert matrix.model.damping.kind == "matrix"
    result = matrix.run(at_hz=[120.0], stability=False, progress=False)
    assert result.converged.all()


def test_a_matrix_must_have_two_dimensions():
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_matrices(np.ones(3), np.eye(3), sectors=4)
    assert caught.value.key == "model.mass"
