"""The names of an Integer's values: one rule (language.value_names), carried by the
flat variable, used by results, comparisons and the teaching page alike."""

from acausal import Eq, Integer, Model
from acausal.compiler.flatten import flatten
from acausal.language import Component, value_names


class Base:
    Off = 0
    On = 1


class Derived(Base):
    Idle = 1      # the most derived class names a value first
    Ready = 2
    count = 3     # not capitalised: not a value name
    Flag = True   # a Boolean, not an Integer value
    MAX = 2       # all capitals: a limit, not a value name
    _Hidden = 3


def test_capitalised_int_constants_name_the_values_the_nearest_class_first():
    assert value_names(Derived, 0, 2) == ((0, "Off"), (1, "Idle"), (2, "Ready"))


def test_no_names_unless_every_value_in_the_bounds_has_one():
    assert value_names(Derived, 0, 3) == ()      # 3 has no proper name
    assert value_names(Derived, None, 2) == ()   # no lower bound
    assert value_names(Derived, 0, 1000) == ()   # too many values to name


class Switch(Component):
    Off = 0
    On = 1
    state = Integer(start=0, fixed=True, min=Off, max=On)
    count = Integer(start=0, fixed=True)

    def equations(self):
        return [Eq(self.state, 1), Eq(self.count, 2)]


class Panel(Model):
    def build(self):
        self.switch = Switch()


def test_the_flat_variable_carries_the_names_of_its_values():
    variables = flatten(Panel()).variable_map
    assert variables["switch.state"].labels == ((0, "Off"), (1, "On"))
    assert variables["switch.count"].labels == ()  # no bounds: no names
