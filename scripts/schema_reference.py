#!/usr/bin/env python3
"""Prints the key tables of docs/scene-format.md "Key reference" from docs/scene.schema.json.

Usage: scripts/schema_reference.py > /tmp/ref.md  (then paste it over that section).
"""
import json,sys
PIPE=chr(92)+'|'
import os
REPO=os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
s=json.load(open(os.path.join(REPO,'docs','scene.schema.json'),encoding='utf-8'))
d=s['$defs']
def typ(p):
    if '$ref' in p: return p['$ref'].split('/')[-1]
    if 'enum' in p: return (' '+PIPE+' ').join('`'+str(e)+'`' for e in p['enum'])
    if 'oneOf' in p or 'anyOf' in p: return ' or '.join(typ(x) for x in p.get('oneOf',p.get('anyOf')))
    t=p.get('type','')
    if t=='array' and 'items' in p and isinstance(p['items'],dict): return f"array of {typ(p['items'])}"
    return t if isinstance(t,str) else '/'.join(t)
def table(props, required=()):
    rows=['| key | value | meaning |','|---|---|---|']
    for k,p in props.items():
        desc=p.get('description','') if isinstance(p,dict) else ''
        if isinstance(p,dict) and 'items' in p and isinstance(p['items'],dict) and not desc:
            desc=p['items'].get('description','')
        req=' (required)' if k in required else ''
        ty=typ(p) if isinstance(p,dict) else ''
        desc=desc.replace('|', PIPE)
        rows.append(f"| `{k}`{req} | {ty} | {desc} |")
    return '\n'.join(rows)
out=[]
def section(title, obj, intro=''):
    out.append(f'### {title}\n')
    if intro: out.append(intro+'\n')
    if 'properties' in obj: out.append(table(obj['properties'], obj.get('required',[]))+'\n')
def sub(name, obj):
    # nested arrays of objects and nested objects, recursively
    for k,p in obj.get('properties',{}).items():
        if isinstance(p,dict) and p.get('type')=='array' and isinstance(p.get('items'),dict) and 'properties' in p['items']:
            section(f'`{name}.{k}[]`', p['items'])
            sub(f'{name}.{k}[]', p['items'])
        elif isinstance(p,dict) and p.get('type')=='object' and 'properties' in p:
            section(f'`{name}.{k}`', p)
            sub(f'{name}.{k}', p)
top=s['properties']
out.clear()


section('`materials[]`', d['material'])
section('`contactPairs[]`', d['contactPair'])
section('`contact`', d['contactSettings'])
section('`medium`', top['medium'])
section('`environment`', d['environment'])
sub('environment', d['environment'])
section('`environment.ground`, `environment.planes[]`', d['plane'])
section('`environment.heightfields[]`', d['heightfield'])
for branch in d['object']['allOf']:
    tp=branch.get('if',{}).get('properties',{}).get('type',{})
    types=tp.get('enum',[tp['const']] if 'const' in tp else [])
    if any(t in ('arm','vehicle','hand') for t in types):
        section('objects of type '+', '.join(f'`{t}`' for t in types), branch['then'])
        sub('objects[].'+types[0], branch['then'])
section('`robotics`', d['robotics'])
sub('robotics', d['robotics'])
section('`control`', d['control'], 'docs/robots.md "Controlling joints".')
section('`control.joints.<name>`, `sequence[].joints.<name>`', d['actuators']['additionalProperties'],
        'A `target` is a number, `{"keyframes": [[t, value], ...], "interpolation": "linear" or "cubic"}` '
        'or `{"sine": {"amplitude", "period", "phase", "offset"}}`.')
sub('control', d['control'])
section('`control.bases[]`, `sequence[].bases[]`', d['bases']['items'])
print('\n'.join(out))
