"""The scene's ground motions other than a sine: records, pulses, stochastic motions, and the
motions made of others (two components, a wave passage, a coherent simulation).

They live apart from :mod:`pframe.model.scene` so that a scene whose motion is a sine (or
none) does not make their models: the scene's unions of motions are made on demand
(:func:`pframe.model.tagged.on_demand`), and this module is imported when a scene first names
one of these kinds. Their names are also :mod:`pframe.model.scene`'s.
"""

import math
from typing import Literal

from pydantic import Field, PrivateAttr, model_validator

from pframe.model.parts import Base, Positive, Sine, SupportName
from pframe.model.tagged import tagged


class Baseline(Base):
    """A polynomial a_c(t) = c_0 + ... + c_p t^p removed from a record's acceleration, its
    velocity and displacement integrated from rest as the record's are
    (pframe.excitation.kinematics.baseline_correct; Boore & Bommer 2005)."""

    fit: Literal["velocity", "displacement", "rest"] = Field(
        "velocity", description="What a_c is fitted to: the velocity or the displacement "
        "(least squares over the record), or rest (the record ends at rest: final velocity "
        "and displacement 0).")
    degree: int = Field(1, ge=0, le=5, description="p, the polynomial's degree (rest: 1 or "
                        "more); 1 with fit velocity: a quadratic velocity baseline through 0.")


class Record(Base):
    """A recorded ground acceleration read from a file (path relative to the YAML file)."""

    kind: Literal["record"] = "record"
    file: str = Field(description="Two columns (time s, acceleration) or a PEER NGA .AT2 file "
                      "(from the PEER NGA-West2 database), relative to the YAML file.")
    format: Literal["auto", "columns", "at2"] = Field(
        "auto", description="File format; auto: PEER for the suffix .AT2 in any case (.AT2, "
                            ".at2, .At2), else two columns. pframe validate prints how the "
                            "file was read.")
    units: Literal["g", "m/s2", "cm/s2", "gal", "mm/s2", "in/s2", "ft/s2"] | None = Field(
        None, description="Acceleration units of the file's values. Default: the units its "
        "header states (PEER: 'UNITS OF G', 'UNITS OF CM/SEC/SEC'; two columns: a comment "
        "'# units: cm/s2'), else g for .AT2 and m/s2 otherwise. Units that contradict the "
        "header are refused.")
    scale: float = Field(1.0, allow_inf_nan=False, description="Factor on the record.")
    pga: Positive | None = Field(
        None, description="Scale the record to this peak ground acceleration, in m/s^2 (not g: "
        "0.4 g is 3.92); instead of scale. pframe validate and solve print the PGA applied, in "
        "m/s^2 and g.")
    period: Literal["mean", "predominant"] | Positive = Field(
        "mean", description="The record's characteristic period T, which sets w_p = 2 pi / T of "
        "its Pi groups and dimensionless output: mean (the mean period T_m of Rathje et al. "
        "1998, 2004, over 0.25-20 Hz), predominant (the period T_p of the peak of the 5%-damped "
        "acceleration spectrum) or a period in seconds of the record as in its file.")
    frequency: Positive | None = Field(
        None, description="Compress or stretch the record's time axis so that its "
        "characteristic circular frequency 2 pi / T is this (rad/s); default: as in the file.")
    displacement: str | None = Field(
        None, description="The record's ground displacement: a PEER .DT2 file (units its "
        "header states, cm) or two columns (time s, displacement m), relative to the YAML "
        "file; the displacement of the supports it moves, instead of the acceleration "
        "integrated twice (checked against it, docs/supports.md#displacements-from-a-record).")
    velocity: str | None = Field(
        None, description="The record's ground velocity with its displacement: a PEER .VT2 "
        "file (cm/s) or two columns (time s, velocity m/s).")
    baseline: Baseline | None = Field(
        None, description="A baseline correction of the record's acceleration (on its own "
        "step, before any scaling; docs/supports.md#displacements-from-a-record); none: the "
        "record as read, its displacement drifting as its acceleration integrates.")

    @model_validator(mode="after")
    def _scale_or_pga(self):
        if self.pga is not None and "scale" in self.model_fields_set:
            raise ValueError("give scale (a factor) or pga (a target peak), not both")
        if self.velocity is not None and self.displacement is None:
            raise ValueError("velocity comes with displacement (the record's two files)")
        if self.displacement is not None and self.baseline is not None:
            raise ValueError("a displacement file is the record's displacement as its "
                             "provider corrected it: give no baseline with it")
        return self

    # The absolute folder ``file`` is relative to, set when the record is read from a scene
    # file: a copy of the scene (model_copy, with or without update) keeps it, so the copy
    # reads the same record from any current folder. Not a field: not in the YAML, the
    # schema or equality.
    _folder: str | None = PrivateAttr(None)

    def __eq__(self, other):
        if not isinstance(other, Record):
            return NotImplemented
        return self.__dict__ == other.__dict__


class _Pulse(Base):
    """Shared by the pulse excitations: amplitude a_p and period T_p (w_p = 2 pi / T_p)."""

    amplitude: float = Field(allow_inf_nan=False, description="Acceleration amplitude a_p "
                             "(m/s^2).")
    period: Positive = Field(description="Pulse period T_p (s); w_p = 2 pi / T_p.")

    @property
    def frequency(self) -> float:
        """The pulse's circular frequency w_p = 2 pi / T_p (rad/s)."""
        return 2.0 * math.pi / self.period

    @property
    def characteristic_acceleration(self) -> float:
        """a_p (m/s^2), the acceleration scale of Pi numbers built on the pulse."""
        return abs(float(self.amplitude))

    @property
    def characteristic_frequency(self) -> float:
        """w_p (rad/s), the frequency scale of Pi numbers built on the pulse."""
        return self.frequency


class Cycloidal(_Pulse):
    """A cycloidal pulse (Makris 1997; Makris & Black 2004): type A a_p sin(w_p t) and type B
    a_p cos(w_p t) for one period, type C_n a_p cos(w_p t + phi) for n + 1/2 - phi/pi periods
    (phi returns the ground to its start); zero afterwards. See docs/gap-audit.md#pulses."""

    kind: Literal["cycloidal"] = "cycloidal"
    type: Literal["A", "B", "C"] = Field(description="A (forward), B (forward and back) or "
                                         "C (n main cycles).")
    n: int = Field(1, ge=1, description="Main cycles of a type-C pulse (C_n); only for type C.")

    @model_validator(mode="after")
    def _n_for_c(self):
        if self.type != "C" and self.n != 1:
            raise ValueError("n (the cycles of a type-C pulse) applies to type C only")
        return self


class Ricker(_Pulse):
    """The Ricker wavelet a_p (1 - 2 pi^2 s^2 / T_p^2) exp(-pi^2 s^2 / T_p^2), s = t - t_0,
    zero after t = 2 t_0. See docs/gap-audit.md#pulses."""

    kind: Literal["ricker"] = "ricker"
    center: Positive | None = Field(None, description="Time t_0 of the central peak (s); "
                                    "default 1.5 T_p (the wavelet is below 1e-8 a_p at t = 0).")


class StochasticParameters(Base):
    """The six parameters of the Rezaeian & Der Kiureghian model, given directly."""

    arias: Positive = Field(description="Expected Arias intensity I_a (m/s; 1 s g = 9.81 m/s).")
    d595: Positive = Field(description="Significant duration D5-95 (s): 5 % to 95 % of I_a.")
    tmid: Positive = Field(description="t_mid (s): when 45 % of I_a is reached.")
    frequency: Positive = Field(description="f_mid (Hz): the filter frequency at t_mid.")
    slope: float = Field(0.0, allow_inf_nan=False, description="f' (Hz/s): the rate of change "
                         "of the filter frequency.")
    damping: float = Field(gt=0, lt=1, allow_inf_nan=False, description="The filter's damping "
                           "ratio zeta_f.")

    @model_validator(mode="after")
    def _feasible(self):
        from pframe.excitation.stochastic import envelope_feasible

        if not envelope_feasible(self.d595, self.tmid):
            raise ValueError(f"d595 {self.d595:g} s and tmid {self.tmid:g} s: no gamma-form "
                             "modulating function has them (d595 / tmid must be below 4.93; "
                             "tmid is counted from the start of the motion)")
        return self


class Jennings(Base):
    """Jennings, Housner & Tsai (1968): (t/t_1)^2 rise, 1 to t_2, then exp(-c (t - t_2))."""

    kind: Literal["jennings"] = "jennings"
    rise: Positive = Field(description="t_1 (s): end of the rise.")
    plateau: Positive = Field(description="t_2 (s): end of the strong phase (>= t_1).")
    decay: Positive = Field(description="c (1/s): the decay rate; the motion ends when the "
                            "envelope is 0.001.")

    @model_validator(mode="after")
    def _order(self):
        if self.plateau < self.rise:
            raise ValueError("plateau (t_2) must not be before rise (t_1)")
        return self


class GammaShape(Base):
    """The gamma form t^(alpha_2 - 1) exp(-alpha_3 t) with peak 1, from D5-95 and t_mid."""

    kind: Literal["gamma"] = "gamma"
    d595: Positive = Field(description="Significant duration D5-95 (s) of the envelope's energy.")
    tmid: Positive = Field(description="t_mid (s): when 45 % of the envelope's energy is reached.")

    @model_validator(mode="after")
    def _feasible(self):
        from pframe.excitation.stochastic import envelope_feasible

        if not envelope_feasible(self.d595, self.tmid):
            raise ValueError(f"d595 {self.d595:g} s and tmid {self.tmid:g} s: no gamma form has "
                             "them (d595 / tmid must be below 4.93)")
        return self


_SITE_FIELDS = ("magnitude", "distance", "vs30")
_CP_FIELDS = ("intensity", "ground_frequency", "ground_damping")


class Stochastic(Base):
    """A simulated ground motion, seeded and reproducible (docs/stochastic-motions.md):
    rezaeian2010 (a site-based modulated filtered white noise, its parameters sampled from
    magnitude, distance, Vs30 and mechanism, or given) or clough_penzien (filtered white
    noise with a modulating function, parameters given)."""

    kind: Literal["stochastic"] = "stochastic"
    model: Literal["rezaeian2010", "clough_penzien"] = Field(
        description="rezaeian2010 (Rezaeian & Der Kiureghian 2008, 2010) or clough_penzien "
                    "(Kanai-Tajimi with filter_frequency 0).")
    seed: int = Field(0, ge=0, description="Seed of the random numbers: the same seed gives "
                      "the same motion.")
    magnitude: Positive | None = Field(None, description="rezaeian2010: moment magnitude M.")
    distance: Positive | None = Field(None, description="rezaeian2010: rupture distance R_rup "
                                      "(km).")
    vs30: Positive | None = Field(None, description="rezaeian2010: Vs30 of the site (m/s).")
    mechanism: Literal["strike_slip", "reverse"] = Field(
        "strike_slip", description="rezaeian2010: faulting mechanism (F = 0 or 1).")
    parameters: StochasticParameters | None = Field(
        None, description="rezaeian2010: the six parameters given (instead of the site).")
    highpass: bool = Field(True, description="rezaeian2010: the 0.2 Hz critically damped "
                           "high-pass post-filter, run on 7.96 s (10 / w_c) past the modulated "
                           "motion until it is at rest: no residual velocity or displacement "
                           "(below 1e-3 of their peaks); the motion is that much longer.")
    intensity: Positive | None = Field(None, description="clough_penzien: white-noise "
                                       "intensity S_0 (m^2/s^3), of the two-sided PSD.")
    ground_frequency: Positive | None = Field(None, description="clough_penzien: w_g (rad/s).")
    ground_damping: Positive | None = Field(None, description="clough_penzien: zeta_g.")
    filter_frequency: float = Field(0.0, ge=0, allow_inf_nan=False, description="clough_penzien:"
                                    " w_f (rad/s) of the high-pass second filter; 0: "
                                    "Kanai-Tajimi.")
    filter_damping: float = Field(0.6, gt=0, allow_inf_nan=False,
                                  description="clough_penzien: zeta_f.")
    envelope: tagged([Jennings, GammaShape], "kind") | None = Field(
        None, description="clough_penzien: modulating function (none: stationary for "
                          "duration).")
    duration: Positive | None = Field(None, description="clough_penzien without envelope: the "
                                      "motion's length (s).")
    step: Positive = Field(0.01, description="Time step of the simulated motion (s); the "
                           "analysis interpolates it linearly.")
    scale: float = Field(1.0, allow_inf_nan=False, description="Factor on the motion.")

    @model_validator(mode="after")
    def _fields_of_model(self):
        given = self.model_fields_set
        if self.model == "rezaeian2010":
            site = [n for n in _SITE_FIELDS if getattr(self, n) is not None]
            if self.parameters is not None and site:
                raise ValueError(f"give the site ({', '.join(_SITE_FIELDS)}) or parameters, not "
                                 "both")
            if self.parameters is None and len(site) < 3:
                missing = [n for n in _SITE_FIELDS if n not in site]
                raise ValueError(f"rezaeian2010 needs magnitude, distance and vs30 (missing: "
                                 f"{', '.join(missing)}) or parameters")
            other = [n for n in (*_CP_FIELDS, "filter_frequency", "filter_damping", "envelope",
                                 "duration") if n in given]
        else:
            missing = [n for n in _CP_FIELDS if getattr(self, n) is None]
            if missing:
                raise ValueError(f"clough_penzien needs {', '.join(missing)}")
            if self.envelope is None and self.duration is None:
                raise ValueError("clough_penzien needs an envelope or a duration")
            if self.envelope is not None and self.duration is not None:
                raise ValueError("give an envelope or a duration, not both")
            other = [n for n in (*_SITE_FIELDS, "mechanism", "parameters", "highpass")
                     if n in given]
        if other:
            raise ValueError(f"{', '.join(other)} do not apply to model {self.model}")
        return self


#: one ground motion along one direction
Motion = tagged([Sine, Record, Cycloidal, Ricker, Stochastic], "kind")


class Components(Base):
    """A ground motion in two horizontal components (docs/plan.md): any motion along x and
    any along y, the pair turned by ``angle`` on the site (the incidence). A pair of PEER
    records of one station is read as a pair: the same event and station, time step and
    length are checked."""

    kind: Literal["components"] = "components"
    x: Motion | None = Field(None, description="The motion along the pair's x axis.")
    y: Motion | None = Field(None, description="The motion along the pair's y axis (at "
                             "angle + 90 degrees).")
    angle: float = Field(0.0, allow_inf_nan=False, description="The angle of the pair's x "
                         "axis from the site's x axis (degrees, counter-clockwise): the "
                         "angle of incidence.")

    @model_validator(mode="after")
    def _one_at_least(self):
        if self.x is None and self.y is None:
            raise ValueError("give the motion along x, along y, or both")
        return self

    def motions(self) -> tuple:
        """(axis, motion) of the components given: 'x', then 'y'."""
        return tuple((axis, m) for axis, m in (("x", self.x), ("y", self.y)) if m is not None)


class WavePassage(Base):
    """One motion reaching each support later as the waves pass (docs/supports.md): at
    support s it is a(t - tau_s), tau_s = (p_s - p_first) . (cos phi, sin phi) / v_app, the
    supports' positions p projected on the direction of propagation phi, counted from the
    support the waves reach first."""

    kind: Literal["wave_passage"] = "wave_passage"
    motion: tagged([Sine, Record, Cycloidal, Ricker, Stochastic, Components], "kind") = Field(
        description="The motion as the waves bring it (at the support they reach first).")
    velocity: Positive = Field(description="The apparent velocity v_app of the waves along "
                               "the ground surface (m/s), typically 200 to 2000 m/s.")
    direction: float = Field(0.0, allow_inf_nan=False, description="The direction the waves "
                             "travel, degrees from the site's x axis (counter-clockwise).")


class Coherency(Base):
    """How alike the motions of two supports are, frequency by frequency, apart from the
    waves' delay (the lagged coherency |gamma(w, d)|; docs/supports.md)."""

    model: Literal["luco_wong", "harichandran_vanmarcke"] = Field(
        description="luco_wong (Luco & Wong 1986) or harichandran_vanmarcke (Harichandran & "
        "Vanmarcke 1986).")
    incoherence: float | None = Field(None, ge=0, allow_inf_nan=False, description="luco_wong: "
                                      "alpha, about 0.1 to 0.5.")
    shear_velocity: Positive | None = Field(None, description="luco_wong: v_s of the ground "
                                            "(m/s).")
    amplitude: float = Field(0.736, ge=0, le=1, allow_inf_nan=False,
                             description="harichandran_vanmarcke: A.")
    alpha: Positive = Field(0.147, description="harichandran_vanmarcke: alpha.")
    k: Positive = Field(5210.0, description="harichandran_vanmarcke: k (m).")
    f0: Positive = Field(1.09, description="harichandran_vanmarcke: f0 (Hz).")
    b: Positive = Field(2.78, description="harichandran_vanmarcke: b.")

    @model_validator(mode="after")
    def _parameters(self):
        if self.model == "luco_wong" and (self.incoherence is None
                                          or self.shear_velocity is None):
            raise ValueError("luco_wong needs incoherence and shear_velocity")
        if self.model == "harichandran_vanmarcke" and (self.incoherence is not None
                                                       or self.shear_velocity is not None):
            raise ValueError("incoherence and shear_velocity are luco_wong's")
        return self


class Coherent(Base):
    """Motions simulated at every support (docs/supports.md): one stochastic motion's
    spectrum and modulating function, made partly incoherent between supports by a coherency
    model, delayed by the waves' passage, filtered by each support's soil column; seeded and
    reproducible. With ``record`` at support ``at``, the others are simulated conditioned on
    it (Konakli & Der Kiureghian 2012)."""

    kind: Literal["coherent"] = "coherent"
    motion: Stochastic = Field(description="The firm-ground motion whose spectrum and "
                               "modulating function every support shares (kind: stochastic: "
                               "clough_penzien, or rezaeian2010 at its mid-time filter).")
    coherency: Coherency | None = Field(None, description="The lagged coherency; none: fully "
                                        "coherent (the supports differ by their delays and "
                                        "soil only).")
    velocity: Positive | None = Field(None, description="The waves' apparent velocity (m/s): "
                                      "each support's motion delayed as they reach it; none: "
                                      "no delay.")
    direction: float = Field(0.0, allow_inf_nan=False, description="The direction the waves "
                             "travel (degrees from the site's x axis).")
    seed: int = Field(0, ge=0, description="Seed of the random numbers: the same seed gives "
                      "the same motions.")
    record: Record | None = Field(None, description="A record the motions are conditioned on: "
                                  "it is the motion of support 'at'.")
    at: SupportName | None = Field(None, description="The support where the record was taken.")

    @model_validator(mode="after")
    def _record_at(self):
        if (self.record is None) != (self.at is None):
            raise ValueError("give record and at together (the record and the support it "
                             "was taken at), or neither")
        return self


