"""Loads the MJCF of a whole PRB mechanism exported by prbfit into MuJoCo, follows one of the
scene's drive paths, lets the mechanism settle at each requested fraction of it, and prints
the settled stage pose and the drive's reactions as JSON.

usage: mujoco_mech_check.py MODEL.xml SPEC.json

SPEC: {"length": L (m), "force": E I0 / L^2 (N), "moment": E I0 / L (N m)   (flexure 1's),
       "drive": [[kind, value], [kind, value], [kind, value]]  for x, y, phi; kind is
                "prescribed" (m, rad) or "loaded" (N, N m),
       "fractions": [f1, f2, ...]}  increasing fractions of the drive path.

How it drives: a prescribed coordinate is the file's joint equality drive_x / drive_y /
drive_phi, switched on, its target polycoef[0] (eq_data[0]) ramped; a loaded coordinate a
generalized force on the stage joint (qfrc_applied), ramped. Both are ramped from one
fraction to the next so the mechanism follows the same branch as prbfit's continuation;
joint damping settles it: about twice critical for each spring, from its stiffness and its
diagonal of the mass matrix, as tests/mujoco_check.py does; none on the stage and coupler
joints, which have no spring (the chains' damping reaches them through the closures; damping
of their own, with no stiffness to scale it by, only slowed the settling). The file's own
time step, solref and solimp are used unchanged.

The reaction of a prescribed coordinate is its drive equality's constraint force on the
stage joint: efc_force of that equality's row times the row's efc_J entry on the joint.

Output: {"cases": [{"fraction", "stage": [dx/L, dy/L, dphi], "stage_load": [ax, ay, beta]
(nondimensional, flexure 1's units; loads as given for loaded coordinates),
"violation": [largest closure residual in position (units of L), in angle (rad)],
"speed": largest joint speed left, "steps": time steps so far, "settled": whether nothing
moved by 1e-14 L over the last window, "unstable": how many times MuJoCo found the
accelerations unstable (and reset the state), which must be 0}]}
"""
import json
import sys

import mujoco
import numpy as np

NAMES = [("stage_x", "drive_x"), ("stage_y", "drive_y"), ("stage_phi", "drive_phi")]
RAMP = 40000  # steps from one fraction to the next (400 / omega of the fastest spring)
CHUNK = 10  # steps between updates of the ramped targets (small: a jump of the target
# would ask the stiff closures for accelerations past MuJoCo's 1e10 guard, which resets)
WINDOW = 800  # steps between convergence checks
MAX_STEPS = 4_000_000


def mass_diagonal(model, data):
    full = np.zeros((model.nv, model.nv))
    try:
        mujoco.mj_fullM(model, data, full)  # MuJoCo >= 3.3
    except TypeError:
        mujoco.mj_fullM(model, full, data.qM)  # older releases
    return np.diag(full).copy()


def reactions(model, data, eq_ids, dofs):
    """The drive equalities' constraint forces on their stage joints (N or N m)."""
    out = [0.0, 0.0, 0.0]
    jac = data.efc_J.reshape(data.nefc, model.nv) if data.nefc else None
    for row in range(data.nefc):
        if data.efc_type[row] != mujoco.mjtConstraint.mjCNSTR_EQUALITY:
            continue
        for c in range(3):
            if data.efc_id[row] == eq_ids[c]:
                out[c] += jac[row, dofs[c]] * data.efc_force[row]
    return out


def closure_violation(model, data, drive_ids):
    """The largest residual of the loop closures: positions (m) and, of welds, angles."""
    position, angle = 0.0, 0.0
    seen = {}
    for row in range(data.nefc):
        eq = data.efc_id[row]
        if data.efc_type[row] != mujoco.mjtConstraint.mjCNSTR_EQUALITY or eq in drive_ids:
            continue
        k = seen.get(eq, 0)
        seen[eq] = k + 1
        # A weld's rows: three of position, then three of orientation.
        if model.eq_type[eq] == mujoco.mjtEq.mjEQ_WELD and k >= 3:
            angle = max(angle, abs(data.efc_pos[row]))
        else:
            position = max(position, abs(data.efc_pos[row]))
    return position, angle


def main():
    path, spec_path = sys.argv[1], sys.argv[2]
    with open(spec_path) as f:
        spec = json.load(f)
    length, force, moment = spec["length"], spec["force"], spec["moment"]
    kinds = [k for k, _ in spec["drive"]]
    ends = np.array([v for _, v in spec["drive"]], dtype=float)
    model = mujoco.MjModel.from_xml_path(path)
    model.opt.jacobian = mujoco.mjtJacobian.mjJAC_DENSE
    data = mujoco.MjData(model)
    joints = [model.joint(j).id for j, _ in NAMES]
    dofs = [model.jnt_dofadr[j] for j in joints]
    qpos = [model.jnt_qposadr[j] for j in joints]
    eq_ids = [model.equality(e).id for _, e in NAMES]
    for c in range(3):
        data.eq_active[eq_ids[c]] = 1 if kinds[c] == "prescribed" else 0

    # Damping: about twice critical for every spring from its stiffness and its diagonal of
    # the mass matrix; none on joints without a spring (stage, coupler pins).
    mujoco.mj_forward(model, data)
    inertia = mass_diagonal(model, data)
    stiffness = np.array([model.jnt_stiffness[model.dof_jntid[i]] for i in range(model.nv)])
    model.dof_damping[:] = 4.0 * np.sqrt(stiffness * inertia)

    steps = 0
    last_fraction = 0.0
    cases = []
    for fraction in spec["fractions"]:
        start = last_fraction
        # Ramp.
        for k in range(0, RAMP, CHUNK):
            s = start + (fraction - start) * min(1.0, (k + CHUNK) / RAMP)
            set_drive(data, kinds, ends * s, eq_ids, dofs, model)
            mujoco.mj_step(model, data, nstep=CHUNK)
            steps += CHUNK
        set_drive(data, kinds, ends * fraction, eq_ids, dofs, model)
        # Settle: until nothing moves by 1e-14 L over a window.
        last = None
        settled = False
        while not settled and steps < MAX_STEPS:
            mujoco.mj_step(model, data, nstep=WINDOW)
            steps += WINDOW
            now = data.qpos.copy()
            settled = last is not None and np.max(np.abs(now - last)) < 1e-14 * length
            last = now
        mujoco.mj_forward(model, data)
        got = reactions(model, data, eq_ids, dofs)
        violation = closure_violation(model, data, eq_ids)
        stage = [
            data.qpos[qpos[0]] / length,
            data.qpos[qpos[1]] / length,
            data.qpos[qpos[2]],
        ]
        loads = []
        for c in range(3):
            unit = moment if c == 2 else force
            value = got[c] if kinds[c] == "prescribed" else ends[c] * fraction
            loads.append(value / unit)
        cases.append(
            {
                "fraction": fraction,
                "stage": stage,
                "stage_load": loads,
                "violation": [violation[0] / length, violation[1]],
                "speed": float(np.max(np.abs(data.qvel))),
                "steps": steps,
                "settled": bool(settled),
                "unstable": int(data.warning[mujoco.mjtWarning.mjWARN_BADQACC].number),
            }
        )
        last_fraction = fraction
    print(json.dumps({"cases": cases}))


def set_drive(data, kinds, values, eq_ids, dofs, model):
    data.qfrc_applied[:] = 0.0
    for c in range(3):
        if kinds[c] == "prescribed":
            model.eq_data[eq_ids[c]][0] = values[c]
        else:
            data.qfrc_applied[dofs[c]] = values[c]


if __name__ == "__main__":
    main()
