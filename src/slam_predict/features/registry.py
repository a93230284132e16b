"""The registry of named features: every feature has a name, a unit and a description, and
belongs to one family (a function computing all of its features at once).

Names are registered once; registering a name again raises ``ValueError`` (families and
features alike), so two modules can never silently provide the same feature.
"""
from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import Any

from slam_predict.errors import InputError, did_you_mean


@dataclass(frozen=True)
class Feature:
    """One feature: ``name`` (the key in feature vectors), ``unit`` and ``doc`` (one line)."""

    name: str
    unit: str
    doc: str
    family: str


@dataclass(frozen=True)
class Family:
    """A feature family: ``compute(context) -> {name: value}`` yields exactly ``features``."""

    name: str
    compute: Callable[[Any], dict[str, float]]
    features: tuple[Feature, ...]


class Registry:
    """Families and features by name, in registration order; duplicates refused."""

    def __init__(self) -> None:
        self._families: dict[str, Family] = {}
        self._features: dict[str, Feature] = {}

    def add_family(self, name: str, compute: Callable[[Any], dict[str, float]],
                   features: Iterable[tuple[str, str, str]]) -> Family:
        """Register family ``name`` with its (feature name, unit, doc) triples."""
        if name in self._families:
            raise ValueError(f"feature family '{name}' is already registered")
        entries = tuple(Feature(n, unit, doc, name) for n, unit, doc in features)
        seen = set()
        for feature in entries:
            if feature.name in self._features or feature.name in seen:
                raise ValueError(f"feature '{feature.name}' is already registered")
            if not feature.unit or not feature.doc:
                raise ValueError(f"feature '{feature.name}' needs a unit and a description")
            seen.add(feature.name)
        family = Family(name, compute, entries)
        self._families[name] = family
        self._features.update({f.name: f for f in entries})
        return family

    def family(self, name: str) -> Family:
        """The family called ``name``; InputError with a hint when unknown."""
        if name not in self._families:
            raise InputError(f"unknown feature family '{name}'"
                             + did_you_mean(name, self._families))
        return self._families[name]

    def feature(self, name: str) -> Feature:
        """The feature called ``name``; InputError with a hint when unknown."""
        if name not in self._features:
            raise InputError(f"unknown feature '{name}'" + did_you_mean(name, self._features))
        return self._features[name]

    @property
    def families(self) -> list[str]:
        """Family names in registration order."""
        return list(self._families)

    def names(self, families: Iterable[str] = ()) -> list[str]:
        """Feature names (of ``families``, default all) in registration order."""
        chosen = list(families) or self.families
        return [f.name for fam in chosen for f in self.family(fam).features]

    def __contains__(self, name: object) -> bool:
        return name in self._features

    def __len__(self) -> int:
        return len(self._features)
