"""Cases: made from TOML, examples and the default; edited by attribute;
written back; pickled; planned; their modes."""

import pickle

import numpy as np
import pytest

import cyclorub


def test_the_default_case_is_the_papers():
    case = cyclorub.Case.default()
    assert case.model.sectors == 24
    assert case.excitation.engine_order == 1
    assert case.excitation.amplitude == 4.0
    assert case.contact.law == "regularized"
    assert case.harmonic_balance.time_samples == 10000
    assert case.continuation.start_hz is None, "absent: the automatic range"


def test_an_empty_file_is_the_default_case(tmp_path):
    path = tmp_path / "case.toml"
    path.write_text("")
    case = cyclorub.Case.from_toml(path)
    assert case.to_dict() == cyclorub.Case.default().to_dict()
    assert case.case_dir == tmp_path


def test_toml_text_and_files_parse_to_the_same_case(tmp_path):
    text = "[contact]\nlaw = \"dlft\"\n\n[excitation]\nengine_order = 3\n"
    path = tmp_path / "case.toml"
    path.write_text(text)
    from_text = cyclorub.Case.from_toml(text)
    from_file = cyclorub.Case.from_toml(str(path))
    assert from_text.to_dict() == from_file.to_dict()
    assert from_text.contact.law == "dlft"
    assert from_text.excitation.engine_order == 3


def test_attribute_edits_set_the_case_file_keys():
    case = cyclorub.Case.default()
    case.contact.law = "dlft"
    case.contact.wall_stiffness = 1e8
    case.model.damping.ratio = 2e-3
    case.excitation.dofs = np.array([1])
    assert case.contact.law == "dlft"
    assert case.contact.wall_stiffness == 1e8
    assert case.model.damping.ratio == 2e-3
    text = case.to_toml()
    assert 'law = "dlft"' in text
    assert cyclorub.Case.from_toml(text).to_dict() == case.to_dict()
    case.contact.wall_stiffness = None
    assert case.contact.wall_stiffness is None, "None makes a key absent"
    assert "contact" in dir(case) and "law" in dir(case.contact)


def test_replace_copies_and_leaves_the_original():
    case = cyclorub.Case.default()
    other = case.replace({"excitation.engine_order": 2, "casing.gap": 5e-4})
    assert other.excitation.engine_order == 2 and other.casing.gap == 5e-4
    assert case.excitation.engine_order == 1
    assert case.copy() == case and case.copy() is not case


def test_every_example_loads_and_the_names_are_the_clis():
    names = cyclorub.Case.examples()
    assert "n24-standing-h4" in names and len(names) == 10
    for name in names:
        cyclorub.Case.example(name).validate()
    case = cyclorub.Case.example("n45-traveling-h17")
    assert case.model.sectors == 45 and case.excitation.engine_order == 17


def test_an_unknown_example_is_refused_with_the_list():
    with pytest.raises(cyclorub.InputError, match="n24-traveling-h1"):
        cyclorub.Case.example("n24-nothing")


def test_a_case_pickles_as_its_toml():
    case = cyclorub.Case.example("n24-standing-h1")
    case.contact.law = "dlft"
    back = pickle.loads(pickle.dumps(case))
    assert back == case


def test_keys_lists_every_key_with_its_doc():
    keys = {k["key"]: k for k in cyclorub.keys()}
    assert "casing.gap" in keys and keys["casing.gap"]["unit"] == "m"
    assert "model.damping.ratio" in keys


def test_the_plan_gives_the_papers_sizes():
    # Table 2 of the paper: N = 24, traveling h = 1: 21 unknowns per
    # contact dof on the traveling-wave basis (one pair per harmonic).
    plan = cyclorub.Case.default().plan()
    assert plan["symmetry"]["unknowns"] == 21
    assert plan["full"]["unknowns"] == 24 * 21
    assert plan["symmetry"]["sampled_sectors"] == 1
    sets = plan["symmetry"]["nodal_diameters"]
    assert len(sets) == 11 and list(sets[1]) == [-1], "harmonic 1 holds the wave (-h, 1)"
    standing = cyclorub.Case.example("n24-standing-h4").plan()
    assert standing["symmetry"]["unknowns"] <= standing["paper"]["unknowns"]


def test_the_modes_are_per_nodal_diameter():
    diameters, frequencies = cyclorub.Case.default().modes()
    assert list(diameters) == list(range(13))
    assert frequencies.shape == (13, 5)
    assert np.all(np.diff(frequencies, axis=1) > 0), "ascending per diameter"
    assert 100 < frequencies[1, 0] < 200, "the excited family near 125 Hz"


def test_set_get_and_to_dict_by_dotted_key():
    case = cyclorub.Case.default()
    assert case.set("casing.order", 8).get("casing.order") == 8
    assert case.get("contact")["law"] == "regularized"
    assert case.to_dict()["casing"]["order"] == 8
    case.casing = {"gap": 2e-3}
    assert case.casing.gap == 2e-3 and case.casing.order == 0, "a whole table replaced"
    assert "N = 24" in repr(case)
    assert "law" in repr(case.contact)
