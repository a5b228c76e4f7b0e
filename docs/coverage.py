"""Write docs/coverage.md: every class of MSL Rotational, Translational, Blocks and Electrical.Analog and how far acausal has it.

Run ``python docs/coverage.py`` from the repository root after adding a
component, an example or a test; ``tests/test_coverage_table.py`` fails when
the committed table differs from what this script writes, so it cannot drift.

A class's state is found from the code, not written by hand:

- **implemented**: the acausal package that mirrors the MSL package
  (``acausal.library.rotational`` for ``Modelica.Mechanics.Rotational.Components``,
  ``acausal.components.rotational`` for its ``Interfaces``, ...) exports a class of
  that name whose Modelica name (its ``modelica_name``, read by
  ``acausal.tools.catalog.msl_name``) is the Modelica class;
- **checked against a reference**: an example in ``examples/`` that declares
  ``modelica_class`` (and so is compared with the Modelica Association's
  reference result) contains an instance of it;
- **checked analytically**: a test function or a test model in ``tests/``
  names it (instantiates it, or passes it on through ``parametrize``), other
  than the declaration checks (``check_declarations`` and
  ``tests/test_library_declarations.py``, which run on every class);
- for an MSL example: **reproduced** when an example declares it as its
  ``modelica_class``.
"""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: The classes of each MSL 4.1.0 package (its package.order), in MSL order.
MSL = {
    "Modelica.Mechanics.Rotational.Components": (
        "Fixed Inertia Disc Spring Damper SpringDamper ElastoBacklash ElastoBacklash2 BearingFriction Brake "
        "Clutch OneWayClutch IdealGear LossyGear IdealPlanetary Gearbox IdealGearR2T IdealRollingWheel "
        "InitializeFlange RelativeStates AngleToTorqueAdaptor TorqueToAngleAdaptor GeneralAngleToTorqueAdaptor "
        "GeneralTorqueToAngleAdaptor"),
    "Modelica.Mechanics.Rotational.Sources": (
        "Position Speed Accelerate Move Torque Torque2 InverseSpeedDependentTorque LinearSpeedDependentTorque "
        "QuadraticSpeedDependentTorque ConstantTorque SignTorque ConstantSpeed TorqueStep EddyCurrentTorque"),
    "Modelica.Mechanics.Rotational.Sensors": (
        "AngleSensor SpeedSensor AccSensor RelAngleSensor RelSpeedSensor RelAccSensor TorqueSensor PowerSensor "
        "MultiSensor"),
    "Modelica.Mechanics.Rotational.Interfaces": (
        "Flange Flange_a Flange_b Support InternalSupport PartialTwoFlanges PartialOneFlangeAndSupport "
        "PartialTwoFlangesAndSupport PartialCompliant PartialCompliantWithRelativeStates "
        "PartialElementaryOneFlangeAndSupport2 PartialElementaryTwoFlangesAndSupport2 "
        "PartialElementaryRotationalToTranslational PartialTorque PartialAbsoluteSensor PartialRelativeSensor "
        "PartialFriction"),
    "Modelica.Mechanics.Rotational.Examples": (
        "First FirstGrounded CompareBrakingTorque Friction CoupledClutches LossyGearDemo1 LossyGearDemo2 "
        "LossyGearDemo3 ElasticBearing Backlash RollingWheel HeatLosses SimpleGearShift EddyCurrentBrake "
        "GenerationOfFMUs OneWayClutch OneWayClutchDisengaged"),
    "Modelica.Mechanics.Translational.Components": (
        "Fixed Mass Rod Spring Damper SpringDamper ElastoGap SupportFriction Brake IdealGearR2T IdealRollingWheel "
        "RollingResistance Vehicle InitializeFlange MassWithStopAndFriction RelativeStates "
        "GeneralForceToPositionAdaptor GeneralPositionToForceAdaptor"),
    "Modelica.Mechanics.Translational.Sources": (
        "Position Speed Accelerate Move Force Force2 InverseSpeedDependentForce LinearSpeedDependentForce "
        "QuadraticSpeedDependentForce ConstantForce SignForce ConstantSpeed ForceStep EddyCurrentForce"),
    "Modelica.Mechanics.Translational.Sensors": (
        "PositionSensor SpeedSensor AccSensor RelPositionSensor RelSpeedSensor RelAccSensor ForceSensor "
        "PowerSensor MultiSensor"),
    "Modelica.Mechanics.Translational.Interfaces": (
        "Flange Flange_a Flange_b Support InternalSupport PartialTwoFlanges PartialOneFlangeAndSupport "
        "PartialTwoFlangesAndSupport PartialRigid PartialCompliant PartialCompliantWithRelativeStates "
        "PartialElementaryOneFlangeAndSupport2 PartialElementaryTwoFlangesAndSupport2 "
        "PartialElementaryRotationalToTranslational PartialForce PartialAbsoluteSensor PartialRelativeSensor "
        "PartialFriction"),
    "Modelica.Mechanics.Translational.Examples": (
        "SignConvention InitialConditions WhyArrows Accelerate CompareBrakingForce Damper Oscillator Sensors "
        "Friction PreLoad ElastoGap Brake HeatLosses EddyCurrentBrake Vehicle GenerationOfFMUs"),
    "Modelica.Blocks.Continuous": (
        "Integrator LimIntegrator Derivative FirstOrder SecondOrder PI PID LimPID "
        "TransferFunction StateSpace Der LowpassButterworth CriticalDamping Filter"),
    "Modelica.Blocks.Sources": (
        "RealExpression IntegerExpression BooleanExpression ContinuousClock Constant Step Ramp "
        "Sine Cosine SineVariableFrequencyAndAmplitude CosineVariableFrequencyAndAmplitude Sinc "
        "ExpSine Exponentials Pulse SawTooth Trapezoid LogFrequencySweep KinematicPTP "
        "KinematicPTP2 TimeTable CombiTimeTable BooleanConstant BooleanStep BooleanPulse "
        "SampleTrigger BooleanTable RadioButtonSource IntegerConstant IntegerStep IntegerTable"),
    "Modelica.Blocks.Math": (
        "InverseBlockConstraints Gain MatrixGain MultiSum MultiProduct MultiSwitch Sum Feedback "
        "Add Add3 Product Division Abs Sign Sqrt Sin Cos Tan Asin Acos Atan Atan2 Sinh Cosh Tanh "
        "Exp Power Exponentiation Log Log10 WrapAngle RealToInteger IntegerToReal BooleanToReal "
        "BooleanToInteger RealToBoolean IntegerToBoolean RectangularToPolar PolarToRectangular "
        "Mean RectifiedMean ContinuousMean RootMeanSquare SignalExtrema ContinuousSignalExtrema "
        "Variance StandardDeviation Harmonic TotalHarmonicDistortion RealFFT Pythagoras Max Min "
        "MinMax LinearDependency Edge BooleanChange IntegerChange"),
    "Modelica.Blocks.Math.UnitConversions": (
        "To_degC From_degC To_degF From_degF To_degRk From_degRk To_deg From_deg To_rpm From_rpm "
        "To_kmh From_kmh To_day From_day To_hour From_hour To_minute From_minute To_litre "
        "From_litre To_kWh From_kWh To_bar From_bar To_gps From_gps"),
    "Modelica.Blocks.MathInteger": (
        "MultiSwitch Sum Product TriggeredAdd"),
    "Modelica.Blocks.MathBoolean": (
        "MultiSwitch And Or Xor Nand Nor Not RisingEdge FallingEdge ChangingEdge OnDelay"),
    "Modelica.Blocks.Nonlinear": (
        "Limiter VariableLimiter SlewRateLimiter DeadZone FixedDelay PadeDelay VariableDelay"),
    "Modelica.Blocks.Logical": (
        "And Or Xor Nor Nand Not Pre Edge FallingEdge Change GreaterThreshold "
        "GreaterEqualThreshold LessThreshold LessEqualThreshold Greater GreaterEqual Less "
        "LessEqual ZeroCrossing LogicalSwitch Switch Hysteresis OnOffController "
        "TriggeredTrapezoid Timer LogicalDelay RSFlipFlop AssertCondition TerminateSimulation"),
    "Modelica.Blocks.Discrete": (
        "Sampler ZeroOrderHold FirstOrderHold UnitDelay TransferFunction StateSpace "
        "TriggeredSampler TriggeredMax"),
    "Modelica.Blocks.Routing": (
        "Replicator IntegerReplicator BooleanReplicator ExtractSignal Extractor Multiplex "
        "Multiplex2 Multiplex3 Multiplex4 Multiplex5 Multiplex6 DeMultiplex DeMultiplex2 "
        "DeMultiplex3 DeMultiplex4 DeMultiplex5 DeMultiplex6 RealPassThrough IntegerPassThrough "
        "BooleanPassThrough"),
    "Modelica.Blocks.Tables": (
        "CombiTable1Ds CombiTable1Dv CombiTable2Ds CombiTable2Dv"),
    "Modelica.Blocks.Interaction.Show": (
        "RealValue IntegerValue BooleanValue"),
    "Modelica.Blocks.Noise": (
        "GlobalSeed UniformNoise NormalNoise TruncatedNormalNoise BandLimitedWhiteNoise"),
    "Modelica.Blocks.Examples": (
        "PID_Controller Filter FilterWithDifferentiation FilterWithRiseTime SlewRateLimiter "
        "InverseModel ShowLogicalSources LogicalNetwork1 RealNetwork1 IntegerNetwork1 "
        "BooleanNetwork1 Interaction1 BusUsage Rectifier6pulseFFT Rectifier12pulseFFT "
        "TotalHarmonicDistortion Modulation SinCosEncoder CompareSincExpSine "
        "DemonstrateSignalExtrema DemonstrateContinuousSignalExtrema DemoSignalCharacteristic"),
    "Modelica.Blocks.Examples.Noise": (
        "UniformNoise AutomaticSeed Distributions UniformNoiseProperties NormalNoiseProperties "
        "Densities ImpureGenerator ActuatorWithNoise DrydenContinuousTurbulence"),
    "ModelicaTest.Blocks": (
        "Continuous Continuous_SteadyState Continuous_InitialState Continuous_InitialOutput "
        "SelfResettingIntegrator ResetHoldIntegrator LimResetIntegrator IntegratorForceState "
        "Limiters StrictLimiters LimitersHomotopy KinematicPTP UnitDeduction Logical IntegerTable "
        "BooleanTable RootMeanSquare FirstOrderHold OnDelay Mean ConversionBlocks PadeDelay1 "
        "PadeDelay2 Discrete Hysteresis MuxDemux LimPID Exponentiation ZeroThresholds"),
    "Modelica.Electrical.Analog.Interfaces": (
        "Pin PositivePin NegativePin TwoPin OnePort FourPin TwoPort ConditionalHeatPort "
        "PartialConditionalHeatPort AbsoluteSensor RelativeSensor VoltageSource CurrentSource "
        "IdealSemiconductor IdealSwitch IdealSwitchWithArc"),
    "Modelica.Electrical.Analog.Basic": (
        "Ground Resistor Conductor Capacitor Inductor SaturatingInductor Transformer "
        "M_Transformer Gyrator RotationalEMF TranslationalEMF VCV VCC CCV CCC OpAmp OpAmpDetailed "
        "VariableResistor VariableConductor VariableCapacitor VariableInductor Potentiometer "
        "GeneralCurrentToVoltageAdaptor GeneralVoltageToCurrentAdaptor"),
    "Modelica.Electrical.Analog.Ideal": (
        "IdealDiode IdealThyristor IdealGTOThyristor IdealTwoWaySwitch IdealIntermediateSwitch "
        "ControlledIdealTwoWaySwitch ControlledIdealIntermediateSwitch IdealOpAmp IdealOpAmp3Pin "
        "IdealOpAmpLimited IdealizedOpAmpLimited IdealTransformer Idle Short IdealOpeningSwitch "
        "IdealClosingSwitch ControlledIdealOpeningSwitch ControlledIdealClosingSwitch "
        "OpenerWithArc CloserWithArc ControlledOpenerWithArc ControlledCloserWithArc IdealTriac "
        "AD_Converter DA_Converter"),
    "Modelica.Electrical.Analog.Semiconductors": (
        "Diode Diode2 ZDiode NMOS PMOS NPN PNP Thyristor SimpleTriac"),
    "Modelica.Electrical.Analog.Sources": (
        "SignalVoltage ConstantVoltage StepVoltage RampVoltage SineVoltage CosineVoltage "
        "SineVoltageVariableFrequencyAndAmplitude CosineVoltageVariableFrequencyAndAmplitude "
        "ExpSineVoltage ExponentialsVoltage PulseVoltage SawToothVoltage TrapezoidVoltage "
        "LightningImpulseVoltage TableVoltage SupplyVoltage SignalCurrent ConstantCurrent "
        "StepCurrent RampCurrent SineCurrent CosineCurrent "
        "SineCurrentVariableFrequencyAndAmplitude CosineCurrentVariableFrequencyAndAmplitude "
        "ExpSineCurrent ExponentialsCurrent PulseCurrent SawToothCurrent TrapezoidCurrent "
        "LightningImpulseCurrent TableCurrent LightningImpulse DCPowerSupply"),
    "Modelica.Electrical.Analog.Sensors": (
        "PotentialSensor VoltageSensor CurrentSensor PowerSensor MultiSensor"),
    "Modelica.Electrical.Analog.Examples": (
        "CauerLowPassAnalog CauerLowPassOPV CauerLowPassSC CharacteristicIdealDiodes "
        "CharacteristicThyristors ChuaCircuit DifferenceAmplifier HeatingMOSInverter "
        "HeatingNPN_NORGate HeatingPNP_NORGate Resistor HeatingRectifier NandGate "
        "OvervoltageProtection Rectifier ShowSaturatingInductor ShowVariableResistor "
        "SwitchWithArc ThyristorBehaviourTest AmplifierWithOpAmpDetailed CompareTransformers "
        "ControlledSwitchWithArc SimpleTriacCircuit IdealTriacCircuit AD_DA_conversion "
        "GenerationOfFMUs ResonanceCircuits InvertingAmp SeriesResonance ParallelResonance "
        "DemonstrateLightning DemoPowerSupply DemoPowerSupplyWithBuffer"),
    "Modelica.Electrical.Analog.Examples.OpAmps": (
        "NonInvertingAmplifier InvertingAmplifier DifferentialAmplifier Adder Subtracter "
        "Differentiator Integrator LowPass HighPass ControlCircuit VoltageFollower Comparator "
        "InvertingSchmittTrigger SchmittTrigger Multivibrator SignalGenerator LCOscillator"),
}

#: Where acausal keeps the classes of each MSL package.
HOME = {
    "Modelica.Mechanics.Rotational.Components": "acausal.library.rotational",
    "Modelica.Mechanics.Rotational.Sources": "acausal.library.rotational",
    "Modelica.Mechanics.Rotational.Sensors": "acausal.library.rotational",
    "Modelica.Mechanics.Rotational.Interfaces": "acausal.components.rotational acausal.components.friction",
    "Modelica.Mechanics.Translational.Components": "acausal.library.translational",
    "Modelica.Mechanics.Translational.Sources": "acausal.library.translational",
    "Modelica.Mechanics.Translational.Sensors": "acausal.library.translational",
    "Modelica.Mechanics.Translational.Interfaces": "acausal.components.translational",
    "Modelica.Blocks.Continuous": "acausal.library.blocks.continuous acausal.library.blocks.filters",
    "Modelica.Blocks.Sources": "acausal.library.blocks.sources acausal.library.blocks.booleans",
    "Modelica.Blocks.Math": "acausal.library.blocks.math acausal.library.blocks.booleans",
    "Modelica.Blocks.Math.UnitConversions": "acausal.library.blocks.unit_conversions",
    "Modelica.Blocks.MathInteger": "acausal.library.blocks.math_integer",
    "Modelica.Blocks.MathBoolean": "acausal.library.blocks.math_boolean",
    "Modelica.Blocks.Nonlinear": "acausal.library.blocks.nonlinear",
    "Modelica.Blocks.Logical": "acausal.library.blocks.logical",
    "Modelica.Blocks.Discrete": "acausal.library.blocks.discrete",
    "Modelica.Blocks.Routing": "acausal.library.blocks.routing",
    "Modelica.Blocks.Tables": "acausal.library.blocks.tables",
    "Modelica.Blocks.Interaction.Show": "acausal.library.blocks.interaction",
    "Modelica.Blocks.Noise": "acausal.library.blocks.noise",
    "Modelica.Electrical.Analog.Interfaces": "acausal.components.electrical",
    "Modelica.Electrical.Analog.Basic": "acausal.library.electrical",
    "Modelica.Electrical.Analog.Ideal": "acausal.library.electrical",
    "Modelica.Electrical.Analog.Semiconductors": "acausal.library.electrical",
    "Modelica.Electrical.Analog.Sources": "acausal.library.electrical",
    "Modelica.Electrical.Analog.Sensors": "acausal.library.electrical",
}


def implemented(package: str) -> dict[str, type]:
    """MSL class name -> the acausal class that implements it (its ``modelica_name`` is the MSL class)."""
    from acausal.tools.catalog import msl_name

    found = {}
    for home in HOME[package].split():
        try:
            module = importlib.import_module(home)
        except ModuleNotFoundError:
            continue
        for name in MSL[package].split():
            klass = getattr(module, name, None)
            if isinstance(klass, type) and msl_name(klass) == f"{package}.{name}":
                found.setdefault(name, klass)
    return found


def reference_examples() -> dict[str, type]:
    """Modelica class -> the example model (in examples/) that reproduces it."""
    from acausal.language import Model

    sys.path.insert(0, str(ROOT))
    examples = {}
    for path in sorted((ROOT / "examples").glob("*.py")):
        module = importlib.import_module(f"examples.{path.stem}")
        for _, klass in inspect.getmembers(module, inspect.isclass):
            if (issubclass(klass, Model) and klass.__module__ == module.__name__
                    and getattr(klass, "modelica_class", None)):
                examples[klass.modelica_class] = klass
    return examples


def classes_in(model_class: type) -> set[type]:
    """The classes of every component instance in a model (and their bases)."""
    model = model_class()
    model.ensure_built()
    return {base for node in model.walk() for base in type(node).__mro__}


def _library_bindings(tree: ast.Module) -> tuple[dict[str, str], dict[str, str]]:
    """(name -> library module, module alias -> library module) from a test module's imports."""
    names, modules = {}, {}
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("acausal."):
            for alias in node.names:
                target = f"{node.module}.{alias.name}"
                if importlib.util.find_spec(target.rsplit(".", 1)[0]) is not None:
                    names[alias.asname or alias.name] = node.module
                    modules[alias.asname or alias.name] = target
    return names, modules


def analytic_uses() -> dict[type, set[str]]:
    """acausal class -> the test files that instantiate it outside the declaration checks."""
    uses: dict[type, set[str]] = {}
    skip = {"test_library_declarations.py", "library_checks.py"}
    for path in sorted((ROOT / "tests").rglob("*.py")):
        if path.name in skip:
            continue
        tree = ast.parse(path.read_text())
        names, modules = _library_bindings(tree)
        for function in (n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))):
            calls = [n for n in ast.walk(function) if isinstance(n, ast.Call)]
            if any(isinstance(c.func, ast.Name) and c.func.id == "check_declarations" for c in calls):
                continue
            # a class the function (or its parametrize decorator) names: called, or passed on
            for node in ast.walk(function):
                if isinstance(node, (ast.Name, ast.Attribute)):
                    klass = _called_class(node, names, modules)
                    if klass is not None:
                        uses.setdefault(klass, set()).add(str(path.relative_to(ROOT)))
    return uses


def _called_class(func: ast.expr, names: dict[str, str], modules: dict[str, str]):
    if isinstance(func, ast.Name) and func.id in names:
        module, name = names[func.id], func.id
    elif (isinstance(func, ast.Attribute) and isinstance(func.value, ast.Name)
          and func.value.id in modules):
        module, name = modules[func.value.id], func.attr
    else:
        return None
    try:
        value = getattr(importlib.import_module(module), name, None)
    except ModuleNotFoundError:
        return None
    return value if isinstance(value, type) else None


def _short(modelica_class: str) -> str:
    """Modelica.Mechanics.Rotational.Examples.First -> Rotational.First; ModelicaTest.Blocks.X -> X;
    Modelica.Blocks.Examples.Noise.UniformNoise -> Blocks.UniformNoise."""
    parts = modelica_class.split(".")
    if parts[-2] == "Examples":
        return f"{parts[-3]}.{parts[-1]}"
    if parts[-3:-1] in (["Examples", "Noise"], ["Examples", "OpAmps"]):
        return f"{parts[-4]}.{parts[-1]}"
    return parts[-1]


def table() -> str:
    """The text of docs/coverage.md."""
    examples = reference_examples()
    in_reference: dict[type, list[str]] = {}
    for modelica_class, model_class in sorted(examples.items()):
        for klass in classes_in(model_class):
            in_reference.setdefault(klass, []).append(_short(modelica_class))
    analytic = analytic_uses()

    lines = ["# Coverage of MSL Rotational, Translational, Blocks and Electrical.Analog", "",
             "Generated by `python docs/coverage.py` from the library, the examples and the tests "
             "(`tests/test_coverage_table.py` checks that this file is up to date); the rules are in "
             "the script's docstring.", ""]
    totals = []
    for package, members in MSL.items():
        names = members.split()
        lines += [f"## {package}", ""]
        if package.endswith((".Examples", ".Examples.Noise", ".Examples.OpAmps")) or package.startswith("ModelicaTest."):
            lines += ["| example | state | acausal example |", "|---|---|---|"]
            done = 0
            for name in names:
                model = examples.get(f"{package}.{name}")
                if model is not None:
                    done += 1
                    where = f"`examples/{model.__module__.split('.')[-1]}.py`"
                    lines.append(f"| {name} | reproduced, compared with the reference | {where} |")
                else:
                    lines.append(f"| {name} | not yet | |")
            totals.append((package, done, len(names)))
            lines.append("")
            continue
        have = implemented(package)
        lines += ["| class | state | checked by |", "|---|---|---|"]
        for name in names:
            klass = have.get(name)
            if klass is None:
                lines.append(f"| {name} | not yet | |")
                continue
            evidence = []
            if klass in in_reference:
                evidence.append("references: " + ", ".join(sorted(set(in_reference[klass]))))
            if klass in analytic:
                files = sorted(Path(p).name for p in analytic[klass])
                shown = ", ".join(f"`{f}`" for f in files[:3]) + (f" and {len(files) - 3} more" if len(files) > 3 else "")
                evidence.append(f"tests: {shown}")
            state = ("checked against a reference" if klass in in_reference
                     else "checked analytically" if klass in analytic else "implemented")
            lines.append(f"| {name} | {state} | {'; '.join(evidence)} |")
        totals.append((package, len(have), len(names)))
        lines.append("")
    summary = ["## Summary", "", "| package | implemented (examples: reproduced) | of |", "|---|---|---|"]
    summary += [f"| {package} | {done} | {total} |" for package, done, total in totals]
    return "\n".join(lines[:4] + summary + [""] + lines[4:]).rstrip() + "\n"


def main() -> None:
    (ROOT / "docs" / "coverage.md").write_text(table())
    print(f"wrote {ROOT / 'docs' / 'coverage.md'}")


if __name__ == "__main__":
    main()
