# Writes a semlb state (HDF5) as the peer benchmark's binary point set: int n, then n x (float x, y, z, int cell).
import h5py, numpy as np, sys
f = h5py.File(sys.argv[1], 'r')
def walk(g, p=''):
    for k, v in g.items():
        if isinstance(v, h5py.Dataset): print(p + '/' + k, v.shape, v.dtype)
        else: walk(v, p + '/' + k)
walk(f)
pos = np.asarray(f['/elements/position'], dtype=np.float32)
cell = np.asarray(f['/elements/cell']).astype(np.int32)
n = pos.shape[0]
out = np.zeros((n, 4), dtype=np.float32)
out[:, :3] = pos
out[:, 3] = cell.view(np.float32) if cell.dtype == np.int32 else cell.astype(np.int32).view(np.float32)
with open(sys.argv[2], 'wb') as o:
    np.array([n], dtype=np.int32).tofile(o)
    out.tofile(o)
print('wrote', n, 'elements; extent', pos.min(0), pos.max(0))
