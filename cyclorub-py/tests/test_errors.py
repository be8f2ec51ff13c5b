"""Bad input raises a CyclorubError naming the key and the rule."""

import numpy as np
import pytest

import cyclorub


def test_a_refused_value_names_its_key():
    case = cyclorub.Case.default()
    case.casing.gap = -1.0
    with pytest.raises(cyclorub.InputError) as caught:
        case.validate()
    assert caught.value.key == "casing.gap"
    assert "casing.gap = -1" in caught.value.message
    assert caught.value.kind == "case"
    assert isinstance(caught.value, ValueError)
    with pytest.raises(cyclorub.InputError) as caught:
        case.run(progress=False)
    assert caught.value.key == "casing.gap"


def test_an_engine_order_beyond_the_sectors_is_refused():
    case = cyclorub.Case.default()
    case.excitation.engine_order = 30
    with pytest.raises(cyclorub.CyclorubError) as caught:
        case.run(stability=False, progress=False)
    assert caught.value.key == "excitation.engine_order"


def test_toml_text_with_a_bad_value_names_the_key_and_line():
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_toml("[harmonic_balance]\nharmonics = 10\ntime_samples = 5\n")
    assert caught.value.key == "harmonic_balance.time_samples"
    assert ":3" in caught.value.message, "the line of the key"


def test_an_unknown_key_is_refused():
    case = cyclorub.Case.default()
    with pytest.raises(cyclorub.InputError) as caught:
        case.contact.lw = "dlft"
    assert caught.value.key == "contact.lw"
    with pytest.raises(cyclorub.InputError, match="unknown field"):
        cyclorub.Case.from_toml("[contact]\nlw = 1\n")


def test_a_value_of_the_wrong_type_names_the_key():
    case = cyclorub.Case.default()
    with pytest.raises(cyclorub.InputError) as caught:
        case.contact.law = "glue"
    assert caught.value.key == "contact.law"
    assert "regularized" in caught.value.message, "the allowed values"
    with pytest.raises(cyclorub.InputError) as caught:
        case.harmonic_balance.harmonics = "ten"
    assert caught.value.key == "harmonic_balance.harmonics"


def test_a_matrix_that_is_not_symmetric_names_its_key():
    mass = np.eye(2)
    stiffness = np.array([[2.0, -1.0], [-1.5, 2.0]]) * 1e6
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_matrices(mass, stiffness, sectors=4)
    assert caught.value.key == "model.stiffness"
    assert "not symmetric" in caught.value.message


@pytest.mark.parametrize("stiffness, key, words", [
    # Issue 45 item 20: validate() accepted what run() refused.
    (np.array([[1e5, 2e5], [0, 1e5]]), "model.stiffness", "not symmetric"),
    (np.eye(3) * 1e5, "model.mass", "does not match model.stiffness"),
    (-np.eye(2) * 1e5, "model.stiffness", "not positive semidefinite"),
])
def test_matrices_are_checked_where_the_case_is_built(stiffness, key, words):
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_matrices(np.eye(2), stiffness, sectors=24)
    assert caught.value.key == key
    assert words in caught.value.message
    # validate() of a case edited afterwards says the same.
    case = cyclorub.Case.from_matrices(np.eye(2), np.eye(2) * 1e5, sectors=24)
    case.model.stiffness = stiffness
    with pytest.raises(cyclorub.InputError) as caught:
        case.validate()
    assert caught.value.key == key
    assert words in caught.value.message


def test_loading_a_folder_that_does_not_exist_says_so(tmp_path):
    # Issue 45 item 21: it said "HDF5 file nodir/results.h5: I/O error".
    missing = tmp_path / "nodir"
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.load(missing)
    assert "no such folder" in caught.value.message
    assert str(missing) in caught.value.message
    missing.mkdir()
    with pytest.raises(cyclorub.InputError, match="has no results.h5"):
        cyclorub.load(missing)


def test_a_value_refused_by_the_parser_names_its_key():
    # Issue 45 item 22: the message named contact.law, .key was None.
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_toml('[contact]\nlaw = "x"\n')
    assert caught.value.key == "contact.law"
    assert "unknown variant" in caught.value.message
    with pytest.raises(cyclorub.InputError) as caught:
        cyclorub.Case.from_toml("[model.damping]\nratio = [1e-3,\n  \"a\"]\n")
    assert caught.value.key == "model.damping.ratio"


def test_a_dof_out_of_range_names_its_key():
    case = cyclorub.Case.default()
    case.contact.dofs = [9]
    with pytest.raises(cyclorub.InputError) as caught:
        case.run(stability=False, progress=False)
    assert caught.value.key == "contact.dofs"


def test_bad_arguments_are_input_errors(default_result):
    with pytest.raises(cyclorub.InputError):
        cyclorub.Case.default().run(basis="diagonal", progress=False)
    with pytest.raises(cyclorub.InputError) as caught:
        default_result.recover(dof=1, sector=25)
    assert caught.value.key == "sector"
    with pytest.raises(cyclorub.InputError) as caught:
        default_result.recover(dof=6, sector=1)
    assert caught.value.key == "dof"
    with pytest.raises(cyclorub.CyclorubError):
        cyclorub.Case.default().run(at_hz=[-3.0], progress=False)


def test_errors_pickle_with_their_key():
    import pickle

    error = cyclorub.InputError("casing.gap = -1: ...", "casing.gap", "case")
    back = pickle.loads(pickle.dumps(error))
    assert (back.key, back.message, back.kind) == (error.key, error.message, error.kind)
