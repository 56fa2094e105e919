"""All the forms (and expressions) of one problem compiled into ONE FFCx module (one C compile, not one each).

A contact problem needs six to nine forms (the residual and its Jacobian, the virtual-work reaction, the
pressure resultant, the elastic stiffness and the contact Jacobian of the split assembly, a method's nodal
forms); ``dolfinx.fem.form`` compiles each into a module of its own. Each module is one run of the C compiler
with its fixed cost (CFFI, the compiler's start, linking): measured here on a Nitsche Hertz problem's six forms,
5.2 s as six modules against 2.7-3.2 s as one, the assembled values identical. :func:`compile_forms` hands
FFCx the whole list at once (``ffcx.codegeneration.jit.compile_forms``, what ``dolfinx.jit.ffcx_jit`` calls
with a list of one) and builds each ``dolfinx.fem.Form`` from its compiled UFCx form exactly as
``dolfinx.fem.form`` does (the same spaces, coefficients, constants and integration entities). The module is
cached under the signature of the whole list, so a problem of the same structure (scene, method, degree,
kinematics, material model, traction; every number is a Constant, :mod:`fem.coefficients`) loads it again.
Expressions (the surface sampler's fields) can join the same module: FFCx compiles forms and expressions together
(its ``compile_forms`` and ``compile_expressions`` are one pipeline with two declaration lists), and each
``dolfinx.fem.Expression`` is built from its compiled UFCx expression as its constructor does.

Under MPI the forms are compiled on rank 0 first and loaded by the others from the cache (dolfinx's
``mpi_jit_decorator``), as ``dolfinx.fem.form`` does. Importing this module configures the JIT cache's waits and
claims for the whole process (:mod:`fem.jit_cache`).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from collections.abc import Sequence
from pathlib import Path

import dolfinx
import dolfinx.jit
import ffcx
import ffcx.codegeneration.jit as fj
import ffcx.naming
import numpy as np
import ufl
from dolfinx.fem import IntegralType
from dolfinx.fem.forms import Form, form_cpp_class, get_integration_domains

from fem.jit_cache import configure

__all__ = ["compile_forms"]

configure()  # every process that compiles forms waits long and never for a dead claim (fem/jit_cache.py)

_INTEGRAL_TYPES = {"cell": IntegralType.cell, "exterior_facet": IntegralType.exterior_facet,
                   "interior_facet": IntegralType.interior_facet, "vertex": IntegralType.vertex}


def _flat(item, out: list) -> None:
    if isinstance(item, ufl.Form):
        if all(item is not f for f in out):
            out.append(item)
    elif isinstance(item, Sequence) and not isinstance(item, str):
        for sub in item:
            _flat(sub, out)


def _rebuild(item, compiled: dict):
    if isinstance(item, ufl.Form):
        return compiled[id(item)]
    if isinstance(item, Sequence) and not isinstance(item, str):
        return [_rebuild(sub, compiled) for sub in item]
    return item  # None (an empty block) or a form compiled already


def _dolfinx_form(form: ufl.Form, ufcx_form, module, ftype) -> Form:
    """The ``dolfinx.fem.Form`` of one compiled UFL form (what ``dolfinx.fem.form`` builds around ``ffcx_jit``)."""
    sd = form.subdomain_data()
    (domain,) = list(sd.keys())
    mesh = domain.ufl_cargo()
    spaces = [arg.ufl_function_space()._cpp_object for arg in form.arguments()]
    original = form.coefficients()
    coefficients = [original[ufcx_form.original_coefficient_positions[i]]._cpp_object
                    for i in range(ufcx_form.num_coefficients)]
    constants = [c._cpp_object for c in form.constants()]
    ids: dict[str, list] = {kind: [] for kind in sd.get(domain)}
    offsets = [ufcx_form.form_integral_offsets[i] for i in range(len(IntegralType) + 1)]
    for i in range(len(offsets) - 1):
        for j in range(offsets[i], offsets[i + 1]):
            ids[IntegralType(i).name].append(ufcx_form.form_integral_ids[j])
    subdomains = {_INTEGRAL_TYPES[kind]: get_integration_domains(_INTEGRAL_TYPES[kind], data[0], ids[kind])
                  for kind, data in sd.get(domain).items()}
    cpp = ftype([module.ffi.cast("uintptr_t", module.ffi.addressof(ufcx_form))], spaces, coefficients, constants,
                subdomains, [], mesh)
    return Form(cpp, ufcx_form, None, module)


def _dolfinx_expression(expr, points, ufcx_expression, module) -> dolfinx.fem.Expression:
    """The ``dolfinx.fem.Expression`` of one compiled UFL expression (what its constructor builds around
    ``ffcx_jit``; float64)."""
    out = dolfinx.fem.Expression.__new__(dolfinx.fem.Expression)
    out._ufcx_expression, out._ufl_expression, out._code = ufcx_expression, expr, None
    original = ufl.algorithms.extract_coefficients(expr)
    coefficients = [original[ufcx_expression.original_coefficient_positions[i]]._cpp_object
                    for i in range(ufcx_expression.num_coefficients)]
    constants = [c._cpp_object for c in ufl.algorithms.analysis.extract_constants(expr)]
    arguments = ufl.algorithms.extract_arguments(expr)
    if len(arguments) > 1:
        raise ValueError("an Expression takes at most one Argument")
    out._argument_space = arguments[0].ufl_function_space()._cpp_object if arguments else None
    out._cpp_object = dolfinx.cpp.fem.create_expression_float64(
        module.ffi.cast("uintptr_t", module.ffi.addressof(ufcx_expression)), coefficients, constants, [],
        out._argument_space)
    return out


def _compile_module(forms: list, expressions: list, *, options: dict, cache_dir, timeout: int,
                    cffi_extra_compile_args, cffi_verbose, cffi_debug, cffi_libraries):
    """FFCx's ``compile_forms`` for forms and expressions together: one module, cached under the signature of
    all of them (the same steps: signature, claim or load, declarations, compile, load)."""
    objects = [*forms, *expressions]
    module_name = "libffcx_forms_" + ffcx.naming.compute_signature(
        objects, fj._compute_option_signature(options) + fj._compilation_signature(cffi_extra_compile_args, cffi_debug))
    names = [ffcx.naming.form_name(f, i, module_name) for i, f in enumerate(forms)]
    names += [ffcx.naming.expression_name(e, module_name) for e in expressions]
    cache_dir = Path(cache_dir)
    compiled, module = fj.get_cached_module(module_name, names, cache_dir, timeout)
    if compiled is None:
        decl = (fj.UFC_HEADER_DECL.format(np.dtype(options["scalar_type"]).name) + fj.UFC_INTEGRAL_DECL
                + fj.UFC_FORM_DECL + fj.UFC_EXPRESSION_DECL
                + "".join(f"extern ufcx_form {n};\n" for n in names[:len(forms)])
                + "".join(f"extern ufcx_expression {n};\n" for n in names[len(forms):]))
        fj._compile_objects(decl, objects, names, module_name, options, cache_dir, cffi_extra_compile_args,
                            cffi_verbose, cffi_debug, cffi_libraries)  # releases its claim on failure (jit_cache)
        compiled, module = fj._load_objects(cache_dir, module_name, names)
    return compiled, module


def compile_forms(forms: dict, *, comm, expressions: dict | None = None):
    """``forms`` (name -> a UFL form, a list of them or a list of lists, None allowed) compiled into one FFCx
    module; returns the same structure of ``dolfinx.fem.Form`` objects. ``comm``: the communicator that compiles
    (rank 0 first). ``expressions`` (name -> ``(UFL expression, reference points)``): compiled into the same
    module, and then ``(forms, expressions)`` are returned, the latter as ``dolfinx.fem.Expression`` objects."""
    flat: list = []
    for item in forms.values():
        _flat(item, flat)
    exprs = list((expressions or {}).items())
    if not flat and not exprs:
        return (dict(forms), {}) if expressions is not None else dict(forms)
    options = ffcx.get_options({"scalar_type": dolfinx.default_scalar_type})
    jit_options = dolfinx.jit.get_options()
    points = [(e, np.reshape(np.asarray(X, dtype=float), (np.asarray(X).shape[0], -1))) for _, (e, X) in exprs]

    def local():
        return _compile_module(flat, points, options=options, **jit_options)

    compiled, module = dolfinx.jit.mpi_jit_decorator(local)(comm)
    ftype = form_cpp_class(dolfinx.default_scalar_type)
    built = {id(f): _dolfinx_form(f, obj, module, ftype) for f, obj in zip(flat, compiled[:len(flat)], strict=True)}
    out_forms = {name: _rebuild(item, built) for name, item in forms.items()}
    if expressions is None:
        return out_forms
    out_exprs = {name: _dolfinx_expression(e, X, obj, module)
                 for (name, _), (e, X), obj in zip(exprs, points, compiled[len(flat):], strict=True)}
    return out_forms, out_exprs
