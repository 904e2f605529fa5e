"""Reading the binary little-endian PLY files icrkit writes (its default), for
the end-to-end CLI tests: vertex properties and triangle faces."""
import struct

TYPES = {'char': 'b', 'uchar': 'B', 'short': 'h', 'ushort': 'H', 'int': 'i', 'uint': 'I', 'float': 'f', 'double': 'd',
         'int8': 'b', 'uint8': 'B', 'int16': 'h', 'uint16': 'H', 'int32': 'i', 'uint32': 'I', 'float32': 'f',
         'float64': 'd'}


def _header(path):
    data = open(path, 'rb').read()
    end = data.index(b'end_header\n') + len(b'end_header\n')
    header = data[:end].decode('ascii').splitlines()
    assert 'format binary_little_endian 1.0' in header, header[:3]
    return data, end, header


def read(path):
    """({name: (ply type, [values])} of the vertices, [(a, b, c)] faces)."""
    data, end, header = _header(path)
    elements = []  # (name, count, properties); a property is (name, type) or (name, 'list', count type, item type)
    for line in header:
        words = line.split()
        if words[0] == 'element':
            elements.append((words[1], int(words[2]), []))
        elif words[0] == 'property':
            if words[1] == 'list':
                elements[-1][2].append((words[4], 'list', words[2], words[3]))
            else:
                elements[-1][2].append((words[2], words[1]))
    vertices, faces, offset = {}, [], end
    for name, count, props in elements:
        if name == 'vertex':
            row = struct.Struct('<' + ''.join(TYPES[p[1]] for p in props))
            columns = list(zip(*row.iter_unpack(data[offset:offset + count * row.size]))) if count else [() for _ in props]
            vertices = {p[0]: (p[1], list(c)) for p, c in zip(props, columns)}
            offset += count * row.size
        elif name == 'face':
            assert len(props) == 1 and props[0][1] == 'list', props
            count_format, item_format = '<' + TYPES[props[0][2]], TYPES[props[0][3]]
            count_size = struct.calcsize(count_format)
            for _ in range(count):
                (n,) = struct.unpack_from(count_format, data, offset)
                offset += count_size
                item = struct.Struct('<' + item_format * n)
                faces.append(item.unpack_from(data, offset))
                offset += item.size
        else:
            raise AssertionError('unexpected element ' + name)
    return vertices, faces


def vertex_properties(path):
    return read(path)[0]
