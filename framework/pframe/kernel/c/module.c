/* The Python extension module pframe.kernel._ckernel: an empty module, so that pip builds,
 * installs and finds the kernel like any compiled extension. The kernel's functions
 * (kernel.c) use no Python API; pframe/kernel/ckernel.py loads this file with ctypes and
 * calls them, which releases the GIL. Limited API (abi3): one wheel per platform serves every
 * Python from 3.10. */

#ifndef Py_LIMITED_API
#define Py_LIMITED_API 0x030A0000
#endif
#include <Python.h>

static struct PyModuleDef module = {
    PyModuleDef_HEAD_INIT, "_ckernel",
    "pframe's compiled time-stepping kernel (called through ctypes: pframe.kernel.ckernel)",
    -1, NULL, NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__ckernel(void) { return PyModule_Create(&module); }
