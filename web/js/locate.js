// Finds where a JSON pointer (RFC 6901, "/shapes/3/radius") points in JSON text, so that the scene
// editor can select the value an error names. Returns [start, end) offsets, or null when the text
// does not parse or has no such path (then the deepest existing parent is not guessed at).

export function locate(text, pointer) {
  const path = pointer.split('/').slice(1).map(t => t.replace(/~1/g, '/').replace(/~0/g, '~'));
  let i = 0;
  const ws = () => { while (i < text.length && ' \t\n\r'.includes(text[i])) i++; };
  const string = () => {
    const start = i++;
    while (i < text.length && text[i] !== '"') i += text[i] === '\\' ? 2 : 1;
    i++;
    return JSON.parse(text.slice(start, i));
  };
  // Skips one value, or descends when it is on the path; returns [start, end] of the target.
  const value = depth => {
    ws();
    const start = i;
    const target = depth === path.length;
    if (text[i] === '{' || text[i] === '[') {
      const object = text[i] === '{';
      i++;
      let index = 0;
      for (ws(); text[i] !== (object ? '}' : ']'); ws()) {
        if (i >= text.length) throw new Error('unterminated');
        let key = String(index++);
        if (object) {
          key = string();
          ws();
          i++;  // ':'
        }
        if (!target && key === path[depth]) return value(depth + 1);
        const found = value(depth + 1 + path.length);  // never the target
        if (found) return found;
        ws();
        if (text[i] === ',') i++;
      }
      i++;
    } else if (text[i] === '"') {
      string();
    } else {
      while (i < text.length && !',}] \t\n\r'.includes(text[i])) i++;
    }
    return target ? [start, i] : null;
  };
  try {
    return value(0);
  } catch {
    return null;
  }
}
