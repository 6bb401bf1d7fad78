#!/bin/bash
P=/work/main/build/photoncl
for s in cornell-spheres.json cornell-glossy.json furnace-0.8.json gltf-room.gltf; do
  w=64; [[ $s == furnace* ]] && w=32
  for rep in 1 2; do
    for st in kd-tree hash-grid; do
      for m in fg direct; do
        extra=""; [ $m = fg ] && extra="--gather-source estimate"
        out=$($P render /work/main/scenes/$s --width $w --passes 3 --method $m $extra --structure $st -o /tmp/st.exr 2>&1)
        maps=$(echo "$out" | awk '$1=="maps"{print $2}'); ind=$(echo "$out" | awk '$1=="indirect"{print $2}'); dir=$(echo "$out" | awk '$1=="direct"{print $2}'); tot=$(echo "$out" | awk '$1=="total"{print $2}')
        echo "$s $m $st rep$rep maps=$maps direct=$dir indirect=$ind total=$tot"
      done
    done
  done
done
