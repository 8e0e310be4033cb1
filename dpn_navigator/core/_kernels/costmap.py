"""
The Nav2-style costmap's kernels: ray clearing, inflation, block reductions.

Part of the kernel leaf (``core/_kernels``): imports nothing of the core.

"""

import math

from .jit import kernel


@kernel
def inflate(lethal, layer_x0, layer_y0, layer_res, x0, y0, res, radius, inflated):
    """Mark ``inflated`` cells whose centre is within ``radius`` of a ``lethal`` centre."""
    rows, cols = inflated.shape
    reach = int(math.ceil(radius / res)) + 1
    bound = radius * radius + 1e-9
    for i in range(lethal.shape[0]):
        for j in range(lethal.shape[1]):
            if not lethal[i, j]:
                continue
            x = layer_x0 + (j + 0.5) * layer_res
            y = layer_y0 + (i + 0.5) * layer_res
            home_r = int(math.floor((y - y0) / res))
            home_c = int(math.floor((x - x0) / res))
            for rr in range(max(home_r - reach, 0), min(home_r + reach + 1, rows)):
                centre_y = y0 + (rr + 0.5) * res
                for cc in range(max(home_c - reach, 0), min(home_c + reach + 1, cols)):
                    centre_x = x0 + (cc + 0.5) * res
                    if (centre_x - x) ** 2 + (centre_y - y) ** 2 <= bound:
                        inflated[rr, cc] = True


@kernel
def clear_rays(start_rr, start_cc, end_rr, end_cc, max_cells, factor, lethal, known_free,
               cleared):
    """
    Clear the layer cells of Nav2's ``raytraceLine`` from one start cell to each end cell.

    Sets ``lethal`` False and ``known_free`` True on every cell a line visits (as
    `bresenham_cells` lists them), and ``cleared`` True on the planning cell (``factor``
    layer cells a side) that holds it.
    """
    for k in range(end_rr.shape[0]):
        d_rr = end_rr[k] - start_rr
        d_cc = end_cc[k] - start_cc
        abs_rr = abs(d_rr)
        abs_cc = abs(d_cc)
        sign_rr = 1 if d_rr > 0 else -1
        sign_cc = 1 if d_cc > 0 else -1
        distance = math.sqrt(d_rr * d_rr + d_cc * d_cc)
        scale = 1.0 if distance == 0.0 else min(1.0, max_cells / distance)
        if abs_cc >= abs_rr:
            abs_a, abs_b = abs_cc, abs_rr
        else:
            abs_a, abs_b = abs_rr, abs_cc
        end = min(int(scale * abs_a), abs_a)
        error = abs_a // 2
        along_b = 0
        for step in range(end + 1):
            if abs_cc >= abs_rr:
                rr = start_rr + sign_rr * along_b
                cc = start_cc + sign_cc * step
            else:
                rr = start_rr + sign_rr * step
                cc = start_cc + sign_cc * along_b
            lethal[rr, cc] = False
            known_free[rr, cc] = True
            cleared[rr // factor, cc // factor] = True
            error += abs_b
            if error >= abs_a and abs_a > 0:
                along_b += 1
                error -= abs_a


@kernel
def any_in_blocks(layer_mask, factor, cells):
    """Set ``cells[i // factor, j // factor]`` wherever ``layer_mask[i, j]`` is True."""
    for i in range(layer_mask.shape[0]):
        row = i // factor
        for j in range(layer_mask.shape[1]):
            if layer_mask[i, j]:
                cells[row, j // factor] = True
