"""What the form compiler makes (forms, elements, expressions), compiled
once per run, not once per mesh.

The compiled ufcx form (its generated C kernels and their module) depends
on the integrand's expression, the elements, the integrals' types, subdomain
ids and metadata, and how many coefficients and constants of which element
and shape the form has, not on the mesh. dolfinx.fem.form finds the module
of a form again by its UFL signature, which it computes by hashing the whole
expression graph at every call; every step's new mesh makes every form new
and pays that again. Here the compiled form is looked up by a key the
caller gives for the expression (`recipe`: a name and every Python number
the expression has in it) and by the form's layout, which is cheap to read:
integrals, elements, constants' shapes. A DOLFINx Form for the new mesh is
then built from it exactly as dolfinx.fem.form builds one (the same C++
constructor with the mesh's spaces, coefficients, constants and subdomain
data), so the kernels, and the numbers, are those dolfinx.fem.form gives.

Function spaces and expressions (dolfinx.fem.Expression) go the same way:
their compiled element and expression are looked up by the element, and by
the expression's recipe, points and layout.

A recipe must name everything of the expression that the layout does not
show: two expressions with the same recipe and layout share one compiled
form. With CHECK set, every lookup also computes the UFL signature and
raises if it differs from the compiled form's (the tests do that).
"""
from __future__ import annotations

import ffcx.naming
import numpy as np
import ufl
from dolfinx import cpp as _cpp
from dolfinx import fem, jit
from dolfinx.fem.forms import FormMetaClass
from petsc4py import PETSc
from ufl.algorithms import extract_arguments, extract_coefficients
from ufl.algorithms.analysis import extract_constants

from .. import interrupt

#: compute the UFL signature at every lookup and compare it with the
#: compiled form's (costs what the cache saves; for tests)
CHECK = False

# the parameters dolfinx.fem.form passes for PETSc's scalar type: the same
# ones give the same generated code
_SCALAR = {np.dtype(np.float64): ("double", _cpp.fem.Form_float64)}
_FORM_CLASSES = {}
_COMPILED = {}   # (recipe, dtype, layout) -> (ufcx form, module, code, UFL signature)
_ELEMENTS = {}   # repr(UFL element) -> ((ufcx element, ufcx dofmap), module)
_EXPRESSIONS = {}   # (recipe, points, dtype, layout) -> (ufcx expression, module, code, UFL signature)


class SignatureMismatch(AssertionError):
    """A recipe and layout that two different expressions share."""


def _jit(comm, obj, **kwargs):
    """jit.ffcx_jit(comm, obj, ...) with Ctrl-C and SIGTERM held until it
    returns. FFCx claims a module of its cache by creating the module's
    C file (empty) and gives the claim up on an Exception only: a
    KeyboardInterrupt inside would leave it, and every later process would
    wait for that module (FFCx's timeout, 10 s) and fail with "JIT
    compilation timed out". A stop waits for one compilation at most (a
    module not yet in the cache; a few seconds)."""
    with interrupt.deferred():
        return jit.ffcx_jit(comm, obj, **kwargs)


def _layout(f: ufl.Form) -> tuple:
    """What the compiled form depends on besides the expression graph, as
    strings (FFCx changes elements in place: see fem.mesh)."""
    integrals = tuple((i.integral_type(), repr(i.subdomain_id()), repr(sorted(i.metadata().items())),
                       repr(i.ufl_domain().ufl_coordinate_element())) for i in f.integrals())
    arguments = tuple((a.number(), repr(a.part()), repr(a.ufl_element())) for a in f.arguments())
    coefficients = tuple(repr(c.ufl_element()) for c in f.coefficients())
    constants = tuple(c.ufl_shape for c in f.constants())
    return integrals, arguments, coefficients, constants


def compiled(f: ufl.Form, recipe: tuple, dtype=PETSc.ScalarType):
    """(ufcx form, module, code) of the UFL form `f`, compiled at the first
    call with this recipe and layout."""
    dtype = np.dtype(dtype)
    key = (recipe, dtype.str, _layout(f))
    hit = _COMPILED.get(key)
    if hit is None:
        mesh = f.ufl_domain().ufl_cargo()
        ufcx_form, module, code = _jit(mesh.comm, f, form_compiler_params={"scalar_type": _SCALAR[dtype][0]},
                                       jit_params={})
        hit = _COMPILED[key] = (ufcx_form, module, code, f.signature())
    elif CHECK and f.signature() != hit[3]:
        raise SignatureMismatch(f"recipe {recipe!r}: a form of another expression than the compiled one")
    return hit[:3]


def form(f: ufl.Form, recipe: tuple, dtype=PETSc.ScalarType):
    """The DOLFINx Form of the UFL form `f` on its mesh, as
    dolfinx.fem.form(f) makes it, with the compiled form of its recipe."""
    return Prepared(f, recipe, dtype).form()


class Prepared:
    """The UFL form `f` compiled (by its recipe) and read once (spaces,
    coefficients, constants: walking its expression graph is most of what a
    DOLFINx Form costs), from which DOLFINx Forms are made on other cell
    subdomains of the same mesh: the interaction integral's one form
    restricted to the cells near each tip in turn."""

    def __init__(self, f: ufl.Form, recipe: tuple, dtype=PETSc.ScalarType):
        dtype = np.dtype(dtype)
        self.ufcx_form, self._module, self._code = ufcx_form, _, _ = compiled(f, recipe, dtype)
        sd = f.subdomain_data()
        self._subdomains, = list(sd.values())
        domain, = list(sd.keys())
        self._mesh = domain.ufl_cargo()
        self._V = [a.ufl_function_space()._cpp_object for a in f.arguments()]
        coefficients = f.coefficients()
        self._coeffs = [coefficients[ufcx_form.original_coefficient_position[i]]._cpp_object
                        for i in range(ufcx_form.num_coefficients)]
        self._constants = [c._cpp_object for c in f.constants()]
        cls = _FORM_CLASSES.get(dtype)
        if cls is None:
            cls = _FORM_CLASSES[dtype] = type("Form", (FormMetaClass, _SCALAR[dtype][1]), {})
        self._cls = cls

    def form(self, cell=None):
        """The DOLFINx Form; cell: meshtags of the cells for the form's
        dx(i) integrals instead of the subdomain data `f` was written with
        (the same mesh and dimension)."""
        sd = self._subdomains
        subdomains = {_cpp.fem.IntegralType.cell: sd.get("cell") if cell is None else cell,
                      _cpp.fem.IntegralType.exterior_facet: sd.get("exterior_facet"),
                      _cpp.fem.IntegralType.interior_facet: sd.get("interior_facet"),
                      _cpp.fem.IntegralType.vertex: sd.get("vertex")}
        return self._cls(self.ufcx_form, self._V, self._coeffs, self._constants, subdomains, self._mesh,
                         self._module.ffi, self._code)


def count() -> int:
    """How many forms have been compiled (distinct recipe and layout)."""
    return len(_COMPILED)


def function_space(mesh, element: ufl.FiniteElementBase) -> fem.FunctionSpace:
    """fem.FunctionSpace(mesh, element), with the element compiled once."""
    key = repr(element)
    hit = _ELEMENTS.get(key)
    if hit is None:
        (ufcx_element, ufcx_dofmap), module, _ = _jit(mesh.comm, element)
        hit = _ELEMENTS[key] = ((ufcx_element, ufcx_dofmap), module)
    (ufcx_element, ufcx_dofmap), module = hit
    ffi = module.ffi
    cpp_element = _cpp.fem.FiniteElement(ffi.cast("uintptr_t", ffi.addressof(ufcx_element)))
    cpp_dofmap = _cpp.fem.create_dofmap(mesh.comm, ffi.cast("uintptr_t", ffi.addressof(ufcx_dofmap)),
                                        mesh.topology, cpp_element)
    cppV = _cpp.fem.FunctionSpace(mesh._mesh, cpp_element, cpp_dofmap)
    V = fem.FunctionSpace(mesh, element, cppV)
    V._ufcx_element, V._ufcx_dofmap = ufcx_element, ufcx_dofmap   # as fem.FunctionSpace keeps them
    return V


def _expression_layout(e) -> tuple:
    return (e.ufl_shape, repr(e.ufl_domain().ufl_coordinate_element()),
            tuple(repr(a.ufl_element()) for a in extract_arguments(e)),
            tuple(repr(c.ufl_element()) for c in extract_coefficients(e)),
            tuple(c.ufl_shape for c in extract_constants(e)))


def _expression_signature(e, X) -> str:
    return ffcx.naming.compute_signature([(e, X)], "")


def expression(e, points: np.ndarray, recipe: tuple, dtype=PETSc.ScalarType) -> fem.Expression:
    """fem.Expression(e, points) with the expression compiled once per
    recipe, points and layout."""
    dtype = np.dtype(dtype)
    X = np.reshape(points, (points.shape[0] if points.ndim == 2 else 1, -1))
    mesh = e.ufl_domain().ufl_cargo()
    key = (recipe, X.tobytes(), X.shape, dtype.str, _expression_layout(e))
    hit = _EXPRESSIONS.get(key)
    if hit is None:
        ufcx_expression, module, code = _jit(mesh.comm, (e, X), form_compiler_params={"scalar_type": _SCALAR[dtype][0]},
                                             jit_params={})
        hit = _EXPRESSIONS[key] = (ufcx_expression, module, code, _expression_signature(e, X))
    elif CHECK and _expression_signature(e, X) != hit[3]:
        raise SignatureMismatch(f"recipe {recipe!r}: an expression other than the compiled one")
    ufcx_expression, module, code, _ = hit
    # what fem.Expression.__init__ does after the compilation
    out = fem.Expression.__new__(fem.Expression)
    out._ufcx_expression, out._code, out._ufl_expression = ufcx_expression, code, e
    coefficients = extract_coefficients(e)
    coeffs = [coefficients[ufcx_expression.original_coefficient_positions[i]]._cpp_object
              for i in range(ufcx_expression.num_coefficients)]
    constants = [c._cpp_object for c in extract_constants(e)]
    arguments = extract_arguments(e)
    out._argument_function_space = arguments[0].ufl_function_space()._cpp_object if arguments else None
    create = {np.dtype(np.float64): _cpp.fem.create_expression_float64}[dtype]
    ffi = module.ffi
    out._cpp_object = create(ffi.cast("uintptr_t", ffi.addressof(ufcx_expression)), coeffs, constants, mesh,
                             out._argument_function_space)
    return out
