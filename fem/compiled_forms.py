"""All the forms of one problem compiled into ONE FFCx module (one C compile instead of one per form).

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

Under MPI the forms are compiled on rank 0 first and loaded by the others from the cache (dolfinx's
``mpi_jit_decorator``), as ``dolfinx.fem.form`` does. Importing this module configures the JIT cache's waits and
claims for the whole process (:mod:`fem.jit_cache`).
"""

from __future__ import annotations

import dolfinx_solver  # noqa: F401  (MPI ordering, before dolfinx)

from collections.abc import Sequence

import dolfinx
import dolfinx.jit
import ffcx
import ffcx.codegeneration.jit
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


def _dolfinx_form(form: ufl.Form, ufcx_form, module, code, ftype) -> Form:
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
    return Form(cpp, ufcx_form, code, module)


def compile_forms(forms: dict, *, comm) -> dict:
    """``forms`` (name -> a UFL form, a list of them or a list of lists, None allowed) compiled into one FFCx
    module; returns the same structure of ``dolfinx.fem.Form`` objects. ``comm``: the communicator that compiles
    (rank 0 first)."""
    flat: list = []
    for item in forms.values():
        _flat(item, flat)
    if not flat:
        return dict(forms)
    dtype = dolfinx.default_scalar_type
    options = ffcx.get_options({"scalar_type": dtype})
    jit_options = dolfinx.jit.get_options()

    def local():
        return ffcx.codegeneration.jit.compile_forms(flat, options=options, **jit_options)

    objects, module, code = dolfinx.jit.mpi_jit_decorator(local)(comm)
    ftype = form_cpp_class(dtype)
    compiled = {id(f): _dolfinx_form(f, obj, module, code, ftype) for f, obj in zip(flat, objects, strict=True)}
    return {name: _rebuild(item, compiled) for name, item in forms.items()}
