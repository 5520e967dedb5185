"""Structure.validate and Structure3D.validate: the same fault, the same one-line message in
the plane and in space (lamodel.validation words it once), each naming the body or contact."""
import dataclasses

import numpy as np
import pytest

from lamodel.errors import InputError
from lamodel.io.jsonspec import structure_from_json

from builders3d import stack_of_boxes
from conftest import stack_spec


def plane():
    return structure_from_json(stack_spec(2))        # ground, b1, b2; contacts c1 (ground|b1), c2 (b1|b2)


def space():
    return stack_of_boxes(2, 1.0, 1.0, 1.0)          # ground, B1, B2; interfaces j0 (ground|B1), j1 (B1|B2)


def refused(s, **change):
    """The message of validate() on ``s`` with fields replaced (arrays copied first)."""
    fields = {f.name: getattr(s, f.name) for f in dataclasses.fields(s)}
    fields = {k: (v.copy() if isinstance(v, np.ndarray) else list(v) if isinstance(v, list) else v)
              for k, v in fields.items()}
    for key, edit in change.items():
        fields[key] = edit(fields[key]) if callable(edit) else edit
    with pytest.raises(InputError) as e:
        type(s)(**fields).validate()
    message = str(e.value)
    assert "\n" not in message and message.startswith("structure 'stack2': "), message
    return message.split(": ", 1)[1]


def at(index, value):
    """An edit setting entry ``index`` of an array to ``value``."""
    def edit(arr):
        arr[index] = value
        return arr
    return edit


def test_valid_structures_pass():
    assert plane().validate().n_blocks == 2 and space().validate().n_blocks == 2


SHARED = [  # (2D change, 3D change, the message either way; {c} is "contact 'c2'" or "interface 'j1'")
    (dict(blocks=[], centroid=np.zeros((0, 2)), dead=np.zeros((0, 2)), live=np.zeros((0, 2)), dead_m=None,
          live_m=None),
     dict(blocks=[], centroid=np.zeros((0, 3)), dead=np.zeros((0, 3)), live=np.zeros((0, 3)), dead_m=None,
          live_m=None, volume=None),
     "the set of blocks is empty; expected at least one movable block"),
    (dict(blocks=["b1", "b1"]), dict(blocks=["B1", "B1"]), "block '{b}' is declared twice; expected unique ids"),
    (dict(supports=["b1"]), dict(supports=["B1"]), "'{b}' is both a block and a support; expected one or the other"),
    (dict(dead=at((0, 1), np.nan)), dict(dead=at((0, 2), np.inf)),
     "dead of {block} is not a finite number; expected finite values"),
    (dict(block_b=at(1, "nowhere")), dict(iface_b=at(1, "nowhere")),
     "{c} names unknown {end} 'nowhere'; expected a declared block or support"),
    (dict(block_a=at(1, "b2")), dict(iface_a=at(1, "B2")),
     "{c} joins '{b2}' to itself; expected two different bodies"),
    (dict(mu=at(1, -0.5)), dict(mu=at(5, -0.5)), "mu of {c} is -0.5; expected a friction coefficient >= 0"),
    (dict(block_b=at(1, "b1"), block_a=at(1, "ground")), dict(iface_b=at(1, "B1"), iface_a=at(1, "ground")),
     "block '{b2}' touches nothing (a free body); expected every block to have a contact"),
    (dict(live=np.zeros((2, 2))), dict(live=np.zeros((2, 3))),
     "every live load is zero; expected a live load for alpha to multiply"),
]


@pytest.mark.parametrize("change2, change3, words", SHARED)
def test_the_same_fault_has_the_same_words_in_the_plane_and_in_space(change2, change3, words):
    names2 = dict(b="b1", b2="b2", block="'b1'", c="contact 'c2'", end="block_b")
    names3 = dict(b="B1", b2="B2", block="block 'B1'", c="interface 'j1'", end="body b")
    assert refused(plane(), **change2) == words.format(**names2)
    assert refused(space(), **change3) == words.format(**names3)


def test_what_differs_keeps_its_own_words():
    assert refused(plane(), d=at(0, 0.0)) == "d of contact 'c1' is 0; expected a half-length > 0"
    assert refused(plane(), normal=at(0, [0.0, 2.0])) == \
        "normal of contact 'c1' has length 2; expected a unit vector"
    assert refused(space(), tangent1=at(4, [0.0, 0.0, 1.0])) == (
        "the frame (n, t1, t2) of a contact point of interface 'j1' is not orthonormal and right-handed; "
        "expected unit normal and tangents")
    assert refused(space(), point=at(6, np.nan)) == \
        "point of a contact point of interface 'j1' is not a finite number; expected finite values"
