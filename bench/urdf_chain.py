#!/usr/bin/env python3
"""Writes a URDF chain of N links (0.1 kg, a 2 cm box each) joined by revolute or
fixed joints: the import-size figures of issue 40 (bench/results, tests/urdf/
test_urdf_budget.cpp builds the same chain).

    bench/urdf_chain.py 5000 revolute > chain5000.urdf
"""
import sys


def chain(links: int, joint: str) -> str:
    out = ['<robot name="chain">']
    for i in range(links):
        out.append(
            f'<link name="l{i}"><inertial><mass value="0.1"/><inertia ixx="1e-4" iyy="1e-4" '
            'izz="1e-4" ixy="0" ixz="0" iyz="0"/></inertial><collision><geometry><box '
            'size="0.02 0.02 0.02"/></geometry></collision></link>')
    limit = ('<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
             if joint == "revolute" else "")
    for i in range(1, links):
        out.append(f'<joint name="j{i}" type="{joint}"><parent link="l{i - 1}"/><child '
                   f'link="l{i}"/><origin xyz="0.03 0 0"/>{limit}</joint>')
    out.append("</robot>")
    return "\n".join(out) + "\n"


if __name__ == "__main__":
    if len(sys.argv) != 3 or sys.argv[2] not in ("revolute", "fixed"):
        sys.exit("usage: urdf_chain.py LINKS revolute|fixed")
    sys.stdout.write(chain(int(sys.argv[1]), sys.argv[2]))
