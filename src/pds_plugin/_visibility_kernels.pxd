from libc.stdint cimport int64_t

cdef struct Chords:
    # the chords of a ChordBundle (see _visibility_kernels.pyx), as raw pointers into
    # the bundle's arrays (the caller keeps the bundle alive)
    const double *xy            # (m, 2, 2): chord e runs from xy[e, 0] to xy[e, 1]
    const int64_t *prev         # (m,): the chord before chord e along its ring
    const int64_t *out          # (n,): each point's outgoing chord, -1 if none
    const int64_t *start        # CSR lists of the chords near each grid cell
    const int64_t *items
    double x0, y0, h
    Py_ssize_t nx, ny
    bint empty                  # no chords: every point sees every point

cdef struct ChordGrid:
    # the square cells of side h of a chord grid, from (x0, y0)
    double x0, y0, h
    Py_ssize_t nx, ny

cdef struct CellMarks:
    # the two-phase fill of the CSR lists of :func:`bin_chords_by` (count, then place)
    int64_t *stamp              # the last chord marked in each cell
    int64_t *count
    int64_t *items
    int64_t *fill
    Py_ssize_t chord
    bint counting

# A cell rule calls ``mark_cell`` for every cell of ``grid`` that the chord from
# (xa, ya) to (xb, yb) must be listed in, given its reach (at least every cell within
# ``reach`` of it; a cell may be marked more than once).
ctypedef void (*CellRule)(double xa, double ya, double xb, double yb, double reach,
                          const ChordGrid *grid, CellMarks *marks) noexcept nogil

cdef tuple bin_chords_by(chords, reach, ChordGrid grid, CellRule rule)


cdef inline void mark_cell(CellMarks *m, Py_ssize_t c) noexcept nogil:
    """List the current chord in cell c (once)."""
    if m.stamp[c] == m.chord:
        return
    m.stamp[c] = m.chord
    if m.counting:
        m.count[c + 1] += 1
    else:
        m.items[m.fill[c]] = m.chord
        m.fill[c] += 1


cdef Chords chords_of(vis) except *
cdef int orient_sign(double ax, double ay, double bx, double by, double cx,
                     double cy) noexcept nogil
cdef int incircle_sign(double adx, double ady, double bdx, double bdy, double cdx,
                       double cdy) noexcept nogil
cdef bint exact_difference(double a, double b, double *difference) noexcept nogil
cdef bint sees_near_chords(double ax, double ay, Py_ssize_t a_out, double bx, double by,
                           Py_ssize_t b_out, const Chords *c, Py_ssize_t k) noexcept nogil
cdef bint box_seen_near_chords(double px, double py, Py_ssize_t p_out, double bx, double by,
                               double size, double tol, const Chords *c,
                               Py_ssize_t k) noexcept nogil


# The tests below are inline (compiled into each kernel module that cimports them): far
# from the boundary, which is almost everywhere, they are one lookup and no call.

cdef inline Py_ssize_t chord_cell(double x, double y, const Chords *c) noexcept nogil:
    """The chord grid's cell of (x, y), clamped to the grid."""
    cdef Py_ssize_t ix = min(max(<Py_ssize_t>((x - c.x0) / c.h), 0), c.nx - 1)
    cdef Py_ssize_t iy = min(max(<Py_ssize_t>((y - c.y0) / c.h), 0), c.ny - 1)
    return iy * c.nx + ix


cdef inline bint near_boundary(double x, double y, const Chords *c) noexcept nogil:
    """True if some chord is within ``reach`` of the cell of (x, y)."""
    if c.empty:
        return False
    cdef Py_ssize_t k = chord_cell(x, y, c)
    return c.start[k + 1] > c.start[k]


cdef inline bint sees(double ax, double ay, Py_ssize_t a_out, double bx, double by,
                      Py_ssize_t b_out, const Chords *c) noexcept nogil:
    """Is the segment ab inside the closed region bounded by the chords? (b within
    ``reach`` of a; see ``sees_near_chords``.) With no chord near a none can block, and
    neither a nor b is a chord vertex."""
    if c.empty:
        return True
    cdef Py_ssize_t k = chord_cell(ax, ay, c)
    if c.start[k + 1] == c.start[k]:
        return True
    return sees_near_chords(ax, ay, a_out, bx, by, b_out, c, k)


cdef inline bint box_seen(double px, double py, Py_ssize_t p_out, double bx, double by,
                          double size, double tol, const Chords *c) noexcept nogil:
    """Does p see every point of the box [bx, bx+size]² that lies in the region? (see
    ``box_seen_near_chords``; yes when no chord is near p)."""
    if c.empty:
        return True
    cdef Py_ssize_t k = chord_cell(px, py, c)
    if c.start[k + 1] == c.start[k]:
        return True
    return box_seen_near_chords(px, py, p_out, bx, by, size, tol, c, k)


# Exact tests against the region bounded by the chords (``sides`` from cell_sides(vis)):
# is a point strictly inside; is a closed box outside (0), crossing a chord (1) or inside (2).

from libc.stdint cimport int8_t

cdef bint point_inside(const Chords *c, const int8_t *sides, double x,
                       double y) noexcept nogil
cdef int box_state(const Chords *c, const int8_t *sides, double bx, double by,
                   double size) noexcept nogil
