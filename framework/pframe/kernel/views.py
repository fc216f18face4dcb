"""Row views that take no reference: the law arguments of the element loops.

``matrix[e]`` in compiled code makes a new array that holds a reference to the matrix's
memory; numba counts it with atomic increments and decrements, and where a law is called in
one of several branches (the law-id switch) it cannot remove them. Three such views per
element and evaluation cost more than the physics (measured: 60 ns per storey of 6). A row made
by :func:`row` borrows the memory instead: the kernel holds the matrix for as long as the
row is used, so nothing needs counting.
"""

from __future__ import annotations

from numba.core import cgutils, types
from numba.extending import intrinsic
from numba.np.arrayobj import make_array, populate_array


@intrinsic
def row(typingctx, matrix, index):
    """``matrix[index]`` of a C-contiguous 2-D array, borrowing its memory."""
    if not (isinstance(matrix, types.Array) and matrix.ndim == 2 and matrix.layout == "C"):
        return None
    row_type = matrix.copy(ndim=1, layout="C")

    def codegen(context, builder, signature, args):
        source = make_array(signature.args[0])(context, builder, args[0])
        target = make_array(signature.return_type)(context, builder)
        width = builder.extract_value(source.shape, 1)
        start = builder.mul(context.cast(builder, args[1], signature.args[1], types.intp), width)
        populate_array(target, data=builder.gep(source.data, [start]), shape=[width],
                       strides=[source.itemsize], itemsize=source.itemsize, meminfo=None)
        return target._getvalue()

    return row_type(matrix, index), codegen


def _borrow(context, builder, typ, value):
    if isinstance(typ, types.Array):
        array = make_array(typ)(context, builder, value)
        array.meminfo = cgutils.get_null_value(array.meminfo.type)
        array.parent = cgutils.get_null_value(array.parent.type)
        return array._getvalue()
    if isinstance(typ, types.BaseTuple):
        for i, member in enumerate(typ):
            part = _borrow(context, builder, member, builder.extract_value(value, i))
            value = builder.insert_value(value, part, i)
    return value


@intrinsic
def borrowed(typingctx, group):
    """The (named) tuple ``group`` with every array in it borrowing its memory.

    numba counts a reference to every array of a tuple each time it is passed to a compiled
    function (about 1 us for the kernel's groups of arrays, more than a step of the paper's
    scene). The kernel's entry point borrows its groups once; the caller (Python) holds the
    arrays for the whole call, so nothing inside needs counting.
    """
    if not isinstance(group, types.BaseTuple):
        return None

    def codegen(context, builder, signature, args):
        return _borrow(context, builder, signature.args[0], args[0])

    return group(group), codegen
