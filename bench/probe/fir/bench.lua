local w, b = {}, {}
for i = 0, 7 do w[i] = 1 / (i + 2); b[i] = 0 end
local y, p = 0.0, 0
for i = 1, 500000 do
  b[p] = (i % 17) * 0.5
  p = (p + 1) % 8
  y = b[0]*w[0] + b[1]*w[1] + b[2]*w[2] + b[3]*w[3] + b[4]*w[4] + b[5]*w[5] + b[6]*w[6] + b[7]*w[7]
end
print(y)
